"""A battery file's ``ros_timeout`` reaches the ``ros:`` runs: a node that dies ends its
run after that time-out, and the message cites the battery key."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

from tests.interfaces.ros.helpers import NODES
from tests.system_packages import require


def test_battery_ros_timeout_ends_a_run_whose_node_died(tmp_path):
    require("ros")
    shutil.copy(NODES / "failsafe_node.py", tmp_path / "failsafe_node.py")
    battery = tmp_path / "battery.toml"
    battery.write_text('''[battery]
algorithms = ["ros:failsafe_node.py --mode die --robots {robots} --at 0.3"]
ros_timeout = 1.5
time = 2

[[scenarios]]
name = "line"
robots = 2
''')
    done = subprocess.run([sys.executable, "-m", "mimics", "battery", "run", str(battery),
                           "--out", str(tmp_path / "out"), "--workers", "1"],
                          capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode in (0, 1), done.stdout + done.stderr
    (run,) = (tmp_path / "out" / "runs").iterdir()
    summary = json.loads((run / "summary.json").read_text())
    assert summary["status"] == "error"
    assert "within 1.5 s (ros_timeout in the battery file)" in summary["error"]
    assert "t=0.3 s" in summary["error"]  # the node died answering step 3
