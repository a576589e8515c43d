"""Stage lab nodes drive robots unchanged under ``--names stage``'s default (realtime, as
stage_ros runs), against a real ``rosmaster``: an odom callback that skips steps
without a scan, a scan callback, a ``message_filters`` time synchroniser, a
``rospy.Rate`` loop on ``/use_sim_time``, and teleop (``rostopic pub -r 10``); in
lockstep a node that subscribes to the scan 0.5 s after the odometry still gets
step 0's scan, and a node that skips steps no longer stalls the world.

Independent truth: the run's recorded trajectory (the robots moved, by about
what the command asks) and what the nodes received.
"""

from __future__ import annotations

import json
import math
import signal
import subprocess
from pathlib import Path

import pandas as pd

from tests.interfaces.ros.helpers import NODES, SYSTEM_PYTHON, mimics_ros, with_node

NODE = str(NODES / "stage_styles_node.py")
RUN = ("line", "--robots", "2", "--names", "stage", "--param", "random_yaw=false")


def travelled(folder: Path) -> dict[int, float]:
    """Each robot's straight-line distance from its start to its last recorded pose."""
    table = pd.read_parquet(folder / "trajectory.parquet").sort_values(["robot", "step"])
    ends = table.groupby("robot").agg(x0=("x", "first"), y0=("y", "first"),
                                      x1=("x", "last"), y1=("y", "last"))
    return {int(robot): math.hypot(row.x1 - row.x0, row.y1 - row.y0)
            for robot, row in ends.iterrows()}


def node_report(output: str) -> dict:
    return json.loads([line for line in output.splitlines() if line.startswith("{")][-1])


STYLES = ("odom", "scan", "sync", "rate")


def test_each_node_style_drives_its_robots_by_default(ros_env, tmp_path):
    # one run, each style driving two of its eight robots (styles 2k, 2k+1)
    folder = tmp_path / "run"
    nodes = [subprocess.Popen([SYSTEM_PYTHON, NODE, "--style", style, "--first", str(2 * k)],
                              env=ros_env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True) for k, style in enumerate(STYLES)]
    try:
        bridge = mimics_ros(ros_env, "line", "--robots", "8", "--names", "stage", "--param",
                            "random_yaw=false", "--time", "3", "--startup-grace", "3",
                            "--out", str(folder))
    finally:
        for node in nodes:
            node.send_signal(signal.SIGINT)
        outputs = [node.communicate(timeout=30)[0] for node in nodes]
    assert bridge.returncode == 0, bridge.stderr[-2000:]
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["ros"]["mode"] == "realtime"
    assert summary["status"] == "time_limit"
    for style, output in zip(STYLES, outputs, strict=True):
        assert node_report(output)["commands"] > 20, style
    # 0.5 m/s asked for 3 s, the robot accelerating first: clearly moved, never faster
    for robot, distance in travelled(folder).items():
        assert 0.5 < distance <= 0.5 * 3 + 1e-6, (STYLES[robot // 2], robot, distance)


def test_teleop_alone_drives_a_robot(ros_env, tmp_path):
    folder = tmp_path / "run"
    teleop = subprocess.Popen(["rostopic", "pub", "-r", "10", "/robot_0/cmd_vel",
                               "geometry_msgs/Twist", "{linear: {x: 0.5}}"], env=ros_env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        bridge = mimics_ros(ros_env, *RUN, "--time", "3", "--out", str(folder))
    finally:
        teleop.send_signal(signal.SIGINT)
        teleop.wait(30)
    assert bridge.returncode == 0, bridge.stderr[-2000:]
    moved = travelled(folder)
    assert moved[0] > 0.5  # driven by teleop
    assert moved[1] == 0.0  # no command: stands (the clock ran all the same)


def test_a_late_scan_subscriber_gets_step_0s_scan_in_lockstep(ros_env, tmp_path):
    folder = tmp_path / "run"
    bridge, output = with_node(ros_env, [SYSTEM_PYTHON, NODE, "--style", "late-scan",
                                         "--late", "0.5"],
                               *RUN, "--lockstep", "--time", "1", "--out", str(folder))
    assert bridge.returncode == 0, bridge.stderr[-2000:]
    assert node_report(output)["first_scan_stamp"] == 0.0


def test_in_lockstep_a_node_that_skips_steps_holds_its_robots_after_the_grace(ros_env,
                                                                              tmp_path):
    # answers even steps only: strict lockstep would wait for step 1 until --timeout
    folder = tmp_path / "run"
    bridge, _ = with_node(ros_env, [SYSTEM_PYTHON, NODE, "--style", "skip"], *RUN,
                          "--lockstep", "--grace", "0.1", "--time", "1", "--out", str(folder))
    assert bridge.returncode == 0, bridge.stderr[-2000:]
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["status"] == "time_limit"
    events = pd.read_parquet(folder / "events.parquet")
    held = events[events["detail"].astype(str).str.contains("within the grace")]
    # steps 1, 3, 5, 7, 9 of each robot (t = 0.1 ... 0.9 s) held, the others answered;
    # a step's log lines are stamped at its end (t + 0.1 s)
    assert sorted(zip(held["robot"], (held["time"] / 0.1).round() - 1, strict=True)) == \
        [(robot, step) for robot in (0, 1) for step in (1, 3, 5, 7, 9)]
    assert min(travelled(folder).values()) > 0.05
