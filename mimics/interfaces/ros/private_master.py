"""A ROS master of this process's own, on a free loopback port.

A run whose controller is a ROS node started by mimics (``ros:`` algorithms,
:mod:`mimics.interfaces.ros.node_algorithm`) talks to a master nobody else
uses: two battery workers never see each other's topics, and a user's
``roscore`` is left alone. The master starts on first use, serves every later
run of the process (``rospy`` joins one master once per process), and stops
when the process exits; on Linux the kernel also kills it if this process dies
without cleaning up (``PR_SET_PDEATHSIG``, set by util-linux's ``setpriv``), so
a killed battery worker leaves no master behind.
"""

from __future__ import annotations

import atexit
import contextlib
import multiprocessing.util
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

from mimics.interfaces.child_processes import dying_with_parent
from mimics.world.errors import MimicsError

#: Seconds a new master may take to accept connections.
START_LIMIT = 20.0
LOOPBACK = "127.0.0.1"

_master: subprocess.Popen[bytes] | None = None
_uri = ""


def free_port() -> int:
    """A TCP port nothing listens on now (the kernel's choice)."""
    with socket.socket() as probe:
        probe.bind((LOOPBACK, 0))
        return int(probe.getsockname()[1])


def _log_folder() -> str:
    """Where this process's master and nodes write ROS's logs (removed at the end)."""
    return os.path.join(tempfile.gettempdir(), f"mimics-ros-{os.getpid()}")


def ros_environment(uri: str) -> dict[str, str]:
    """The environment variables that point ROS at ``uri`` over loopback, logs kept aside."""
    logs = _log_folder()
    return {"ROS_MASTER_URI": uri, "ROS_IP": LOOPBACK, "ROS_HOME": logs, "ROS_LOG_DIR": logs}


def private_master() -> str:
    """The address of this process's master, started if need be.

    Also points this process's environment at it (``ROS_MASTER_URI`` and the
    rest of :func:`ros_environment`), where ``rospy`` looks when it starts.

    Raises:
        MimicsError: when ``rosmaster`` is not installed or does not start.
    """
    global _master, _uri
    if _master is not None and _master.poll() is None:
        return _uri
    rospy = sys.modules.get("rospy")
    if rospy is not None and rospy.core.is_initialized():  # joined another master already
        raise MimicsError("this process is already a ROS node of the master at "
                          f"{os.environ.get('ROS_MASTER_URI', '?')} (`mimics ros` ran here?), "
                          "and rospy joins one master per process: run ros: algorithms in a "
                          "process of their own (mimics run, a battery, a fresh Python)")
    program = shutil.which("rosmaster")
    if program is None:
        raise MimicsError("rosmaster not found: install ROS 1's master with "
                          "`apt-get install python3-rosmaster` (Debian 12 or later)")
    port = free_port()
    uri = f"http://{LOOPBACK}:{port}"
    environment = ros_environment(uri)
    os.environ.update(environment)
    os.environ.pop("ROS_HOSTNAME", None)  # would take precedence over ROS_IP
    _master = subprocess.Popen(dying_with_parent([program, "--core", "-p", str(port)]),
                               env=dict(os.environ), stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL)
    _uri = uri
    # a multiprocessing child (a battery worker) ends with os._exit: no atexit there
    multiprocessing.util.Finalize(None, stop_private_master, exitpriority=100)
    deadline = time.monotonic() + START_LIMIT
    while True:  # until it accepts connections
        try:
            socket.create_connection((LOOPBACK, port), timeout=1).close()
            return uri
        except OSError:
            if _master.poll() is not None or time.monotonic() > deadline:
                stop_private_master()
                raise MimicsError(f"rosmaster did not start on port {port} within "
                                  f"{START_LIMIT:g} s") from None
            time.sleep(0.05)


@atexit.register
def stop_private_master() -> None:
    """Stop the master (at exit; harmless when none runs)."""
    global _master
    master, _master = _master, None
    if master is None:
        return
    stop_process(master, signal.SIGTERM)
    shutil.rmtree(_log_folder(), ignore_errors=True)


def stop_process(process: subprocess.Popen[bytes], first: signal.Signals,
                 grace: float = 5.0) -> None:
    """Send ``first`` (SIGINT: as Ctrl-C, SIGTERM), then SIGKILL after ``grace`` seconds."""
    if process.poll() is not None:
        return
    with contextlib.suppress(ProcessLookupError):
        process.send_signal(first)
    try:
        process.wait(grace)
    except subprocess.TimeoutExpired:
        process.kill()
        with contextlib.suppress(subprocess.TimeoutExpired):
            process.wait(grace)
