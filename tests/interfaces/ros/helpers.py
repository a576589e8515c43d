"""Helpers of the ROS tests: free ports, and running ``mimics ros`` beside a controller node.

Controller nodes run with the system's Python (``/usr/bin/python3``), where
Debian puts rospy, as a user's node would; ``mimics ros`` runs with the
venv's Python and finds ROS itself.
"""

from __future__ import annotations

import signal
import subprocess
import sys
from pathlib import Path

from mimics.interfaces.ros.private_master import free_port as free_port

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
