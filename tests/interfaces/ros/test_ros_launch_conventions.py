"""roslaunch's conventions, against a real ``rosmaster``: a launch file's ``<remap>``,
its node ``name`` (``__name:=``) and a private ``<param>`` reach ``mimics ros``; stage_ros'
``/reset_positions`` answers; ``mimics ros-files`` bakes in what it was given."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

from mimics.interfaces.cli import main
from tests.interfaces.ros.helpers import SYSTEM_PYTHON
from tests.interfaces.ros.test_ros_files import LOAD
from tests.interfaces.ros.test_ros_stopping import master, nodes_of

LAUNCH = """<launch>
  <node name="lab_sim" pkg="mimics_launch" type="mimics_ros" required="true" output="screen"
        args="line --robots 1 --names stage --time 4 --startup-grace 0 --out {out}">
    <remap from="base_scan" to="scan"/>
    <param name="base_watchdog_timeout" value="0.5"/>
  </node>
</launch>
"""


def test_a_launch_file_remaps_renames_and_sets_private_parameters(ros_env, tmp_path):
    assert main(["ros-files", "--out", str(tmp_path / "ros"), "--names", "stage"]) == 0
    launch = tmp_path / "lab.launch"
    folder = tmp_path / "run"
    launch.write_text(LAUNCH.format(out=folder))
    env = {**ros_env, "ROS_PACKAGE_PATH": str(tmp_path / "ros")}
    process = subprocess.Popen(["roslaunch", str(launch)], env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True)
    server = master(ros_env)
    try:
        deadline = time.monotonic() + 90
        while "/reset_positions" not in dict(server.getSystemState()[2]):  # after topics
            assert process.poll() is None, process.communicate()[0][-3000:]
            assert time.monotonic() < deadline, "no /reset_positions"
            time.sleep(0.05)
        publishers, _, services = server.getSystemState()
        topics = {topic: nodes for topic, nodes in publishers}
        assert topics["/scan"] == ["/lab_sim"]  # remapped, and the node is named as launched
        assert "/base_scan" not in topics
        assert dict(services)["/reset_positions"] == ["/lab_sim"]
        called = subprocess.run(["rosservice", "call", "/reset_positions"], env=env,
                                capture_output=True, text=True, timeout=60, check=False)
        assert called.returncode == 0, called.stderr
        output, _ = process.communicate(timeout=90)
    finally:
        if process.poll() is None:
            process.kill()
            process.communicate()
    assert process.returncode == 0, output[-3000:]
    first = json.loads((folder / "summary.json").read_text())
    assert first["status"] == "stopped"  # /reset_positions ended it and started it again
    again = json.loads((tmp_path / "run-reset-1" / "summary.json").read_text())
    assert again["status"] == "time_limit"
    assert again["ros"]["watchdog"] == 0.5  # ~base_watchdog_timeout
    assert again["ros"]["mode"] == "realtime"  # the stage names' default
    assert "/lab_sim" not in nodes_of(server)


def test_ros_files_bakes_in_its_scenario_robots_and_names(ros_env, tmp_path):
    assert main(["ros-files", "--out", str(tmp_path / "ros"), "--names", "stage",
                 "--robots", "3", "--scenario", "cave"]) == 0
    launch = tmp_path / "ros" / "mimics_launch" / "launch" / "mimics.launch"
    env = {**ros_env, "ROS_PACKAGE_PATH": str(tmp_path / "ros")}
    loaded = json.loads(subprocess.run(
        [SYSTEM_PYTHON, "-c", LOAD, str(launch)], env=env, capture_output=True, text=True,
        check=True, timeout=60).stdout)
    nodes = {name: rest for name, *rest in loaded["nodes"]}
    assert nodes["stageros"][:3] == ["mimics_launch", "mimics_ros",
                                     "cave --robots 3 --names stage --publish-map-odom"]


def test_without_out_the_message_names_the_folder_where_the_run_lands(ros_env, tmp_path):
    done = subprocess.run([sys.executable, "-m", "mimics", "ros", "line", "--robots", "1",
                           "--names", "stage", "--time", "0.3", "--startup-grace", "0"],
                          env={**ros_env, "COLUMNS": "1000"}, cwd=tmp_path,
                          capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 0, done.stderr
    said = next(line for line in done.stdout.splitlines() if line.startswith("records in"))
    folder = Path(said.removeprefix("records in ").strip())
    assert folder.is_absolute()  # true wherever the reader is (roslaunch: in $ROS_HOME)
    assert folder.parent == tmp_path / "runs"
    assert (folder / "summary.json").is_file()
