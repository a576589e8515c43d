"""``mimics ros-files``: the roslaunch package it writes loads in roslaunch, brings up
``mimics ros`` against a real master, and its RViz config names topics that exist."""

from __future__ import annotations

import json
import os
import signal
import subprocess
from pathlib import Path

import yaml

from mimics.interfaces.cli import main
from tests.interfaces.ros.helpers import NODES, SYSTEM_PYTHON

# roslaunch's own XML loader (python3-roslaunch), in the system's Python
LOAD = """
import json, sys, roslaunch.config, roslaunch.xmlloader
config = roslaunch.config.ROSLaunchConfig()
roslaunch.xmlloader.XmlLoader().load(sys.argv[1], config, argv=sys.argv[2:], verbose=False)
print(json.dumps({"nodes": [[n.name, n.package, n.type, n.args, n.required]
                            for n in config.nodes],
                  "params": {k: p.value for k, p in config.params.items()}}))
"""


def rviz_topics(path: Path) -> list[str]:
    displays = yaml.safe_load(path.read_text())["Visualization Manager"]["Displays"]
    return [d.get("Topic") or d.get("Marker Topic") for d in displays
            if "Topic" in d or "Marker Topic" in d]


def test_refuses_a_missing_parent_and_existing_files(tmp_path, capsys):
    assert main(["ros-files", "--out", str(tmp_path / "no" / "such")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert not (tmp_path / "no").exists()
    assert main(["ros-files", "--out", str(tmp_path / "ros")]) == 0
    package = tmp_path / "ros" / "mimics_launch"
    before = (package / "launch" / "mimics.launch").read_text()
    assert main(["ros-files", "--out", str(tmp_path / "ros")]) == 2
    assert "already exists" in capsys.readouterr().err
    assert (package / "launch" / "mimics.launch").read_text() == before
    assert os.access(package / "scripts" / "mimics_ros", os.X_OK)


def test_stage_names_put_stage_ros_scan_topics_in_the_rviz_config(tmp_path, capsys):
    assert main(["ros-files", "--out", str(tmp_path / "three"), "--robots", "3",
                 "--names", "stage"]) == 0
    rviz = tmp_path / "three" / "mimics_launch" / "rviz" / "mimics.rviz"
    assert rviz_topics(rviz) == ["/map", "/mimics/markers", "/robot_0/base_scan",
                                 "/robot_1/base_scan", "/robot_2/base_scan"]
    # stage names publish no map -> odom unless asked: the package's RViz, in map, asks
    launch = (tmp_path / "three" / "mimics_launch" / "launch" / "mimics.launch").read_text()
    assert "--robots 3 --names stage --publish-map-odom" in launch
    assert main(["ros-files", "--out", str(tmp_path / "one"), "--robots", "1",
                 "--names", "stage"]) == 0  # stage_ros: no robot_i/ prefix for one robot
    assert rviz_topics(tmp_path / "one" / "mimics_launch" / "rviz" / "mimics.rviz")[-1] == \
        "/base_scan"
    capsys.readouterr()
    assert main(["ros-files", "--out", str(tmp_path / "bad"), "--names", "gazebo"]) == 2
    assert "--names" in capsys.readouterr().err
    assert not (tmp_path / "bad").exists()


def test_launch_file_loads_and_runs_mimics_with_rviz_topics_that_exist(ros_env, tmp_path):
    assert main(["ros-files", "--out", str(tmp_path / "ros"), "--robots", "2"]) == 0
    package = tmp_path / "ros" / "mimics_launch"
    env = {**ros_env, "ROS_PACKAGE_PATH": str(tmp_path / "ros")}
    launch = package / "launch" / "mimics.launch"
    loaded = json.loads(subprocess.run(
        [SYSTEM_PYTHON, "-c", LOAD, str(launch), "scenario:=line", "args:=--robots 2"],
        env=env, capture_output=True, text=True, check=True, timeout=60).stdout)
    nodes = {name: rest for name, *rest in loaded["nodes"]}
    assert nodes["mimics"] == ["mimics_launch", "mimics_ros", "line --robots 2", True]
    assert nodes["rviz"][:2] == ["rviz", "rviz"]
    assert nodes["rviz"][2] == f"-d {package / 'rviz' / 'mimics.rviz'}"
    assert loaded["params"]["/use_sim_time"] is True
    # a real launch (without RViz: no display here) beside a controller node
    folder = tmp_path / "run"
    controller = subprocess.Popen(
        [SYSTEM_PYTHON, str(NODES / "control_node.py"), "--mode", "observe", "--robots", "2"],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        done = subprocess.run(
            ["roslaunch", "mimics_launch", "mimics.launch", "rviz:=false", "scenario:=line",
             f"args:=--robots 2 --time 0.5 --param random_yaw=false --out {folder}"],
            env=env, capture_output=True, text=True, timeout=120, check=False)
    finally:
        controller.send_signal(signal.SIGINT)
        output, _ = controller.communicate(timeout=30)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert json.loads((folder / "summary.json").read_text())["status"] == "time_limit"
    found = json.loads([line for line in output.splitlines() if line.startswith("{")][-1])
    topics = rviz_topics(package / "rviz" / "mimics.rviz")
    assert topics == ["/map", "/mimics/markers", "/robot_0/scan", "/robot_1/scan"]
    assert set(topics) <= set(found["topics"])
    assert {"/tf", "/tf_static"} <= set(found["topics"])  # what the TF display reads
