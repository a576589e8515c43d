"""The command subscriptions count a controller's publisher only once it can deliver.

rospy counts a subscriber's connection as soon as the master names a
publisher, before their TCP handshake; the publisher keeps the connection
only after it, so a command sent in between is lost. Lockstep runs wait for
every robot's first command, so the bridge must not start the run before the
handshakes. Here a hand-made publisher holds its handshake back.
"""

from __future__ import annotations

import subprocess
import sys

SCRIPT = r"""
import io, os, socket, struct, threading, time, xmlrpc.client
from xmlrpc.server import SimpleXMLRPCServer

from mimics.interfaces.ros.system_ros import require_ros
require_ros()
import rospy
from std_msgs.msg import Float64MultiArray

rospy.init_node("mimics", disable_signals=True)
from mimics.interfaces.ros.commands import CommandSubscriber
from mimics.interfaces.ros.inbox import Inbox

inbox = Inbox(1, lockstep=True, timeout=10)
commands = CommandSubscriber(1, inbox, 0.1)

# the publisher: a TCPROS port that accepts and waits, and the XML-RPC API pointing at it
tcp = socket.socket()
tcp.bind(("127.0.0.1", 0))
tcp.listen(1)
api = SimpleXMLRPCServer(("127.0.0.1", 0), logRequests=False, allow_none=True)
api.register_function(lambda caller, topic, protocols:
                      [1, "", ["TCPROS", "127.0.0.1", tcp.getsockname()[1]]], "requestTopic")
threading.Thread(target=api.serve_forever, daemon=True).start()
master = xmlrpc.client.ServerProxy(os.environ["ROS_MASTER_URI"])
master.registerPublisher("/held_back", "/robot_0/cmd", "std_msgs/Float64MultiArray",
                         f"http://127.0.0.1:{api.server_address[1]}/")
tcp.settimeout(20)
peer, _ = tcp.accept()  # the subscriber has connected and waits for our header
time.sleep(0.5)
print("before", commands.cmd[0].get_num_connections(), commands.publishers_connected(0))

def framed(payload):
    return struct.pack("<I", len(payload)) + payload

fields = {"md5sum": Float64MultiArray._md5sum, "type": Float64MultiArray._type,
          "callerid": "/held_back", "topic": "/robot_0/cmd", "tcp_nodelay": "1"}
peer.sendall(framed(b"".join(framed(f"{k}={v}".encode()) for k, v in fields.items())))
deadline = time.monotonic() + 10
while commands.publishers_connected(0) == 0 and time.monotonic() < deadline:
    time.sleep(0.01)
print("after", commands.cmd[0].get_num_connections(), commands.publishers_connected(0))

inbox.expect(0, [0])
buffer = io.BytesIO()
Float64MultiArray(data=[0.5, 1.25, 0.0]).serialize(buffer)
peer.sendall(framed(buffer.getvalue()))
command, notes = inbox.take(0, 0)
print("command", command.kind, command.first, command.second, command.step)
"""


def test_a_publisher_counts_only_after_its_handshake(ros_env: dict[str, str]) -> None:
    done = subprocess.run([sys.executable, "-c", SCRIPT], env=ros_env, capture_output=True,
                          text=True, timeout=60, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    lines = done.stdout.splitlines()
    # rospy already counts the connection; the bridge does not
    assert lines[0] == "before 1 0"
    assert lines[1] == "after 1 1"
    # and the connection then delivers: the command answers step 0
    assert lines[2] == "command reference 0.5 1.25 0"
