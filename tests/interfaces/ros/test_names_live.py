"""Both name sets against a real ``rosmaster``, with a node written as a stage_ros user writes
one (``nodes/stage_user_node.py``): topics, frames, odometry in the ``odom`` frame, its
covariance, the ground truth, and tf2's chain from ``map`` to the laser.

Independent truths: the run's recorded trajectory (true and measured poses),
the closed form of a unicycle at constant speed and turn rate, and the
covariance recomputed here from the poses the node received (the formula
of ``docs/how-to/ros.md``, written out again below).
"""

from __future__ import annotations

import itertools
import json
import math
import os
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from tests.interfaces.ros.helpers import NODES, SYSTEM_PYTHON, with_node
from tests.system_packages import require

NODE = str(NODES / "stage_user_node.py")
SIGMA_TRANSLATION, SIGMA_ROTATION = 0.03, 0.05  # the Pioneer 3-AT's (Stage's odom_error)
DT = 0.1  # the line scenario's step


def read_log(path: Path) -> pd.DataFrame:
    rows = [json.loads(line) for line in path.read_text().splitlines()]
    table = pd.DataFrame(rows)
    table["step"] = (table["stamp"] / 1e9 / DT).round().astype(int)
    return table


def trajectory(folder: Path) -> pd.DataFrame:
    return pd.read_parquet(folder / "trajectory.parquet").set_index(["robot", "step"])


def wrap(angle):
    return (np.asarray(angle) + math.pi) % (2 * math.pi) - math.pi


def in_start_frame(start: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """Poses seen from ``start`` (hand-written: rotate the offsets by -theta0)."""
    c, s = math.cos(start[2]), math.sin(start[2])
    dx, dy = poses[:, 0] - start[0], poses[:, 1] - start[1]
    return np.column_stack([c * dx + s * dy, -s * dx + c * dy, wrap(poses[:, 2] - start[2])])


def expected_covariances(poses: np.ndarray) -> list[np.ndarray]:
    """The documented first-order propagation, one step at a time, written out by hand."""
    covariance = np.zeros((3, 3))
    found = [covariance]
    for (x, y, theta), (x2, y2, theta2) in itertools.pairwise(poses):
        turn = float(wrap(theta2 - theta))
        phi = theta + turn / 2
        d = (x2 - x) * math.cos(phi) + (y2 - y) * math.sin(phi)
        f = np.array([[1, 0, -d * math.sin(phi)], [0, 1, d * math.cos(phi)], [0, 0, 1]])
        g = np.array([[math.cos(phi), -d / 2 * math.sin(phi)],
                      [math.sin(phi), d / 2 * math.cos(phi)], [0, 1]])
        q = np.diag([(SIGMA_TRANSLATION * d) ** 2, (SIGMA_ROTATION * turn) ** 2])
        covariance = f @ covariance @ f.T + g @ q @ g.T
        found.append(covariance)
    return found


def planar_covariance(row: list[float]) -> np.ndarray:
    full = np.array(row).reshape(6, 6)
    return full[np.ix_([0, 1, 5], [0, 1, 5])]


def run_with_node(env: dict, tmp_path: Path, node_args: list[str], *bridge_args: str):
    log = tmp_path / "node.jsonl"
    folder = tmp_path / "run"
    bridge, output = with_node(env, [SYSTEM_PYTHON, NODE, "--log", str(log), *node_args],
                               *bridge_args, "--out", str(folder))
    assert bridge.returncode == 0, bridge.stdout + bridge.stderr + output
    return read_log(log), folder


def test_a_stage_users_node_drives_three_robots_and_finds_the_frames(ros_env, tmp_path):
    messages, folder = run_with_node(
        ros_env, tmp_path, ["--robots", "3", "--names", "stage", "--goals", "3,1;3,2;3,3"],
        "line", "--robots", "3", "--param", "distance=3", "--names", "stage", "--lockstep",
        "--time", "15", "--publish-map-odom")  # the node looks up map -> laser
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["reached_goal"] == 3 and summary["ros"]["names"] == "stage"
    recorded = trajectory(folder)
    for robot in range(3):
        mine = messages[messages.robot == robot]
        odom, truth = mine[mine.kind == "odom"], mine[mine.kind == "truth"]
        scan = mine[mine.kind == "scan"]
        assert set(odom.frame) == {f"robot_{robot}/odom"}
        assert set(odom.child) == set(truth.child) == {f"robot_{robot}/base_footprint"}
        assert set(truth.frame) == {"map"}
        assert set(scan.frame) == {f"robot_{robot}/base_laser_link"}
        assert set(scan.ranges) == {270}
        # odom: zero at t = 0, the odometer's drift after, within its own covariance
        odom = odom.sort_values("step")
        poses = np.array(odom.pose.tolist())
        np.testing.assert_array_equal(poses[0], [0.0, 0.0, 0.0])
        assert odom.step.tolist() == list(range(len(odom)))
        # the ground truth is the recorded true pose, step by step
        # (a robot at its goal goes on publishing, still: the records stop there)
        truth = truth[truth.step.isin(recorded.loc[robot].index)].sort_values("step")
        rows = recorded.loc[robot].loc[truth.step]
        np.testing.assert_allclose(np.array(truth.pose.tolist()),
                                   rows[["x", "y", "theta"]].to_numpy(), rtol=0, atol=1e-12)
        np.testing.assert_allclose(np.array(truth.twist.tolist()), rows[["v", "w"]].to_numpy(),
                                   rtol=0, atol=1e-12)
        # the covariance is the documented formula applied to the odometer's poses
        for got, expected in zip(odom.covariance, expected_covariances(poses), strict=True):
            np.testing.assert_allclose(planar_covariance(got), expected, rtol=1e-9,
                                       atol=1e-15)
        last = planar_covariance(odom.covariance.iloc[-1])
        assert last[0, 0] > 0 and last[2, 2] > 0  # it moved and turned: noise accumulated
        start = recorded.loc[(robot, 0), ["x", "y", "theta"]].to_numpy(dtype=float)
        true_in_odom = in_start_frame(start, rows[["x", "y", "theta"]].to_numpy())
        drift = poses[-1] - true_in_odom[-1]
        assert np.any(drift != 0)  # the odometer is noisy...
        assert np.all(np.abs(drift) <= 5 * np.sqrt(np.diag(last)))  # ...as its covariance says
    # tf2 chains map -> robot_0/odom -> base_footprint -> base_link -> base_laser_link
    # to robot 0's measured pose at the stamp it found
    (found,) = messages[messages.kind == "tf"].itertuples()
    assert found.frame == "robot_0/base_laser_link"
    measured = recorded.loc[(0, found.step), ["x_meas", "y_meas", "theta_meas"]]
    np.testing.assert_allclose(found.pose[:2], measured.to_numpy(dtype=float)[:2], atol=1e-9)
    assert wrap(found.pose[2] - measured.theta_meas) == pytest.approx(0.0, abs=1e-9)


def test_one_robot_has_no_prefix_and_its_odometry_is_the_unicycles(ros_env, tmp_path):
    speed, rate = 0.3, 0.2
    messages, folder = run_with_node(
        ros_env, tmp_path, ["--robots", "1", "--names", "stage", "--twist", f"{speed},{rate}"],
        "line", "--robots", "1", "--param", "random_yaw=false", "--param", "noise=off",
        "--param", "distance=30", "--names", "stage", "--lockstep", "--time", "10",
        "--publish-map-odom")  # the node looks up map -> laser
    odom = messages[messages.kind == "odom"].sort_values("step")
    assert set(odom.frame) == {"odom"} and set(odom.child) == {"base_footprint"}
    assert set(messages[messages.kind == "scan"].frame) == {"base_laser_link"}
    (found,) = messages[messages.kind == "tf"].itertuples()
    assert found.frame == "base_laser_link"
    poses = np.array(odom.pose.tolist())
    np.testing.assert_array_equal(poses[0], [0.0, 0.0, 0.0])
    # without noise the odometer is the true pose seen from the start pose
    recorded = trajectory(folder).loc[0]
    true_poses = recorded.loc[odom.step, ["x", "y", "theta"]].to_numpy()
    np.testing.assert_allclose(poses, in_start_frame(true_poses[0], true_poses), atol=1e-12)
    assert all(not any(row) for row in odom.covariance)  # no odometry noise: covariance 0
    # past the speed loop's transient (about 4 s) the robot is a unicycle at (v, w):
    # x(t) = x0 + v/w (sin(theta0 + w t) - sin(theta0)), y(t) = y0 - v/w (cos(...) - cos(theta0))
    settled = odom[odom.step >= 50]
    x0, y0, theta0 = settled.pose.iloc[0]
    t = (settled.step.to_numpy() - settled.step.iloc[0]) * DT
    radius = speed / rate
    closed_form = np.column_stack([x0 + radius * (np.sin(theta0 + rate * t) - math.sin(theta0)),
                                   y0 - radius * (np.cos(theta0 + rate * t) - math.cos(theta0)),
                                   wrap(theta0 + rate * t)])
    np.testing.assert_allclose(np.array(settled.pose.tolist()), closed_form, atol=1e-5)


def test_mimics_names_carry_odom_pose_and_ground_truth(ros_env, tmp_path):
    messages, folder = run_with_node(
        ros_env, tmp_path, ["--robots", "2", "--names", "mimics", "--twist", "0.4,0.3"],
        "line", "--robots", "2", "--time", "4")  # 3 s past --tf-after: the node's tf2
    # polls in wall time, and a loaded machine once let a 1 s window pass unseen
    recorded = trajectory(folder)
    for robot in range(2):
        mine = messages[messages.robot == robot]
        odom = mine[mine.kind == "odom"].sort_values("step")
        pose = mine[mine.kind == "pose"].sort_values("step")
        truth = mine[mine.kind == "truth"].sort_values("step")
        assert set(odom.frame) == {f"robot_{robot}/odom"}
        assert set(pose.frame) == set(truth.frame) == {"map"}
        assert set(odom.child) == set(pose.child) == {f"robot_{robot}/base_link"}
        assert set(mine[mine.kind == "scan"].frame) == {f"robot_{robot}/laser"}
        poses = np.array(odom.pose.tolist())
        np.testing.assert_array_equal(poses[0], [0.0, 0.0, 0.0])
        for got, expected in zip(odom.covariance, expected_covariances(poses), strict=True):
            np.testing.assert_allclose(planar_covariance(got), expected, rtol=1e-9,
                                       atol=1e-15)
        rows = recorded.loc[robot].loc[pose.step]
        np.testing.assert_allclose(np.array(pose.pose.tolist()),
                                   rows[["x_meas", "y_meas", "theta_meas"]].to_numpy(),
                                   atol=1e-12)
        np.testing.assert_allclose(np.array(truth.pose.tolist()),
                                   rows[["x", "y", "theta"]].to_numpy(), atol=1e-12)
    (found,) = messages[messages.kind == "tf"].itertuples()
    assert found.frame == "robot_0/laser"


def test_ros_algorithm_with_stage_names_in_the_algorithm_string(tmp_path):
    """``ros:--names=stage PROGRAM``: what a battery file writes; here through ``mimics run``."""
    require("ros")
    log = tmp_path / "node.jsonl"
    algorithm = (f"ros:--names=stage {NODE} --robots 2 --names stage --twist 0.3,0.1 "
                 f"--log {log} --tf-after 0.5")
    done = subprocess_mimics("run", "line", algorithm, "--robots", "2", "--time", "1",
                             "--out", str(tmp_path / "run"))
    assert done.returncode == 0, done.stdout + done.stderr
    messages = read_log(log)
    assert set(messages[messages.kind == "odom"].frame) == {"robot_0/odom", "robot_1/odom"}
    assert set(messages[messages.kind == "truth"].child) == {"robot_0/base_footprint",
                                                             "robot_1/base_footprint"}
    assert messages.step.max() == 10  # answered every step of 1 s


def test_ros_names_option_is_checked(tmp_path):
    bad = subprocess_mimics("run", "line", "ros:x.py", "--ros-names", "gazebo", "--time", "1",
                            "--out", str(tmp_path / "a"))
    assert bad.returncode == 2
    assert "--ros-names: expected one of mimics, stage, got 'gazebo'" in bad.stderr
    not_ros = subprocess_mimics("run", "line", "go_to_goal", "--ros-names", "stage",
                                "--out", str(tmp_path / "b"))
    assert not_ros.returncode == 2
    assert "--ros-names: only for ros: and ros2: algorithms" in not_ros.stderr
    names = subprocess_mimics("ros", "line", "--names", "gazebo")
    assert names.returncode == 2
    assert "--names: expected one of mimics, stage, got 'gazebo'" in names.stderr


def subprocess_mimics(*args: str):
    import subprocess

    return subprocess.run([sys.executable, "-m", "mimics", *args], capture_output=True,
                          text=True, timeout=300, check=False,
                          env={**os.environ, "PYTHONUNBUFFERED": "1"})


def test_no_node_names_the_topics_of_the_name_set(ros_env, tmp_path):
    from tests.interfaces.ros.helpers import mimics_ros

    done = mimics_ros(ros_env, "line", "--robots", "1", "--names", "stage", "--lockstep",
                      "--timeout", "0.5", "--out", str(tmp_path / "run"))
    assert done.returncode == 2
    assert ("no controller node for robot 0 within 0.5 s (--timeout sets it) (nothing "
            "subscribes to /odom (or its other topics) or publishes on /cmd_vel; 1 robot "
            "waiting)") in done.stderr
