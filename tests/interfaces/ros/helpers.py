"""Helpers of the ROS tests: free ports, and running ``mimics ros`` beside a controller node.

Controller nodes run with the system's Python (``/usr/bin/python3``), where
Debian puts rospy, as a user's node would; ``mimics ros`` runs with the
venv's Python and finds ROS itself.
"""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path

from mimics.interfaces.ros.private_master import free_port as free_port
from tests.local_servers import stop_process

SYSTEM_PYTHON = "/usr/bin/python3"
NODES = Path(__file__).parent / "nodes"
EXAMPLES = Path(__file__).parents[3] / "examples" / "ros"


def mimics_ros(env: dict[str, str], *args: str,
               timeout: float = 120) -> subprocess.CompletedProcess[str]:
    """``mimics ros ARGS`` in a subprocess (rospy allows one node per process)."""
    return subprocess.run([sys.executable, "-m", "mimics", "ros", *args], env=env,
                          capture_output=True, text=True, timeout=timeout, check=False)


def with_node(env: dict[str, str], node: list[str], *args: str,
              timeout: float = 120) -> tuple[subprocess.CompletedProcess[str], str]:
    """Run a controller node and ``mimics ros ARGS``; returns the bridge's result and the
    node's output. The node is stopped with SIGINT (as Ctrl-C) once the bridge is done."""
    controller = subprocess.Popen(node, env=env, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True)
    try:
        bridge = mimics_ros(env, *args, timeout=timeout)
    finally:
        controller.send_signal(signal.SIGINT)
        try:
            output, _ = controller.communicate(timeout=15)
        except subprocess.TimeoutExpired:
            controller.kill()
            output, _ = controller.communicate()
    return bridge, output


@contextlib.contextmanager
def running_master(ros_home: Path) -> Iterator[dict[str, str]]:
    """A fresh ``rosmaster`` on a free loopback port, stopped at the end: the environment
    that reaches it (``ROS_HOME`` at ``ros_home``)."""
    port = free_port()
    env = {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{port}", "ROS_IP": "127.0.0.1",
           "ROS_HOME": str(ros_home), "PYTHONUNBUFFERED": "1"}
    env.pop("ROS_HOSTNAME", None)
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 15
        while True:  # until the master accepts connections
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                if time.monotonic() > deadline or master.poll() is not None:
                    raise RuntimeError(f"rosmaster did not start on port {port}") from None
                time.sleep(0.05)
        yield env
    finally:
        stop_process(master, grace=10)
