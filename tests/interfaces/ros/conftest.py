"""A real ROS master per test (``ros_env``); helpers are in ``helpers.py``."""

from __future__ import annotations

import os
import socket
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.interfaces.ros.helpers import free_port
from tests.system_packages import require


@pytest.fixture
def ros_env(tmp_path: Path) -> Iterator[dict[str, str]]:
    """The environment of a fresh ``rosmaster`` on a free port (stopped afterwards)."""
    require("ros")
    port = free_port()
    env = {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{port}", "ROS_IP": "127.0.0.1",
           "ROS_HOME": str(tmp_path / "ros_home"), "PYTHONUNBUFFERED": "1"}
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
        master.terminate()
        try:
            master.wait(10)
        except subprocess.TimeoutExpired:
            master.kill()
            master.wait()

