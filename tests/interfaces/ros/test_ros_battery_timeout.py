"""A battery file's ``ros_timeout`` reaches the ``ros:`` runs: a node that dies ends its
run after that time-out, and the message cites the battery key."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

from tests.interfaces.ros.helpers import NODES
from tests.system_packages import require


def run_battery(battery):
    """``mimics battery run`` of ``battery`` on one worker, into ``out`` beside it."""
    return subprocess.run([sys.executable, "-m", "mimics", "battery", "run", str(battery),
                           "--out", str(battery.parent / "out"), "--workers", "1"],
                          capture_output=True, text=True, timeout=300, check=False)


def node_battery(folder, node, text):
    """``battery.toml`` of ``text`` in ``folder``, beside a copy of the test node ``node``."""
    shutil.copy(NODES / node, folder / node)
    battery = folder / "battery.toml"
    battery.write_text(text)
    return battery


def test_battery_ros_timeout_ends_a_run_whose_node_died(tmp_path):
    require("ros")
    battery = node_battery(tmp_path, "failsafe_node.py", '''[battery]
algorithms = ["ros:failsafe_node.py --mode die --robots {robots} --at 0.3"]
ros_timeout = 4
time = 2

[[scenarios]]
name = "line"
robots = 2
''')
    done = run_battery(battery)
    assert done.returncode in (0, 1), done.stdout + done.stderr
    (run,) = (tmp_path / "out" / "runs").iterdir()
    summary = json.loads((run / "summary.json").read_text())
    assert summary["status"] == "error"
    assert "within 4 s (ros_timeout in the battery file)" in summary["error"]
    assert "t=0.3 s" in summary["error"]  # the node died answering step 3


def test_a_node_waiting_on_ros_time_before_subscribing_runs_in_every_battery_run(tmp_path):
    """/use_sim_time is set only once the node has connected and put back after each run:
    a node that sleeps on ROS time before it subscribes starts alike in every run of a
    worker (left set, the second run's node would wait for a clock that waits for it)."""
    require("ros")
    battery = node_battery(tmp_path, "control_node.py", '''[battery]
algorithms = ["ros:control_node.py --mode sleepy --robots {robots}"]
seeds = 2
time = 0.5
ros_timeout = 20

[[scenarios]]
name = "line"
robots = 2
''')
    done = run_battery(battery)
    assert done.returncode == 0, done.stdout + done.stderr
    runs = sorted((tmp_path / "out" / "runs").iterdir())
    assert [json.loads((run / "summary.json").read_text())["status"] for run in runs] == [
        "time_limit", "time_limit"]
