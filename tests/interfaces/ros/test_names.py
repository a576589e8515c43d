"""The name sets, the odometer's frame and covariance, and ``ros:--names=``; no ROS needed."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mimics.engine.dynamics import advance_pose
from mimics.interfaces.ros.names import RosNames
from mimics.interfaces.ros.node_algorithm import SCHEME, NodeCommand
from mimics.interfaces.ros.odometry_frame import OdometerFrames, propagate, relative_poses
from mimics.world.errors import AlgorithmError, MimicsError

NODE = Path(__file__).parent / "nodes" / "stage_user_node.py"


def test_stage_names_are_stageros_names_with_a_prefix_only_for_several_robots():
    one = RosNames("stage", robots=1)
    assert [one.odom(0), one.ground_truth(0), one.scan(0), one.cmd_vel(0), one.goal(0)] == [
        "/odom", "/base_pose_ground_truth", "/base_scan", "/cmd_vel", "/goal"]
    assert [one.odom_frame(0), one.footprint_frame(0), one.base_frame(0),
            one.laser_frame(0)] == ["odom", "base_footprint", "base_link", "base_laser_link"]
    assert one.cmd(0) is None and one.pose(0) is None and one.command_topics(0) == ("/cmd_vel",)
    many = RosNames("stage", robots=4)
    assert [many.odom(3), many.ground_truth(3), many.scan(3), many.cmd_vel(3)] == [
        "/robot_3/odom", "/robot_3/base_pose_ground_truth", "/robot_3/base_scan",
        "/robot_3/cmd_vel"]
    assert [many.odom_frame(3), many.body_frame(3), many.laser_frame(3)] == [
        "robot_3/odom", "robot_3/base_footprint", "robot_3/base_laser_link"]
    # several rangers: numbered, as stageros numbers them
    assert many.scan(3, ranger=1, rangers=2) == "/robot_3/base_scan_1"
    assert many.laser_frame(3, ranger=0, rangers=2) == "robot_3/base_laser_link_0"
    assert many.commands_text() == "/robot_i/cmd_vel"


def test_mimics_names_keep_the_robot_prefix_even_for_one_robot():
    one = RosNames("mimics", robots=1)
    assert [one.odom(0), one.pose(0), one.ground_truth(0), one.scan(0), one.cmd(0),
            one.cmd_vel(0)] == ["/robot_0/odom", "/robot_0/pose", "/robot_0/ground_truth",
                                "/robot_0/scan", "/robot_0/cmd", "/robot_0/cmd_vel"]
    assert [one.odom_frame(0), one.body_frame(0), one.laser_frame(0)] == [
        "robot_0/odom", "robot_0/base_link", "robot_0/laser"]
    assert one.footprint_frame(0) is None
    assert one.commands_text() == "/robot_i/cmd or /robot_i/cmd_vel"
    assert one.commands_text(0) == "/robot_0/cmd or cmd_vel"


def test_an_unknown_name_set_is_refused():
    with pytest.raises(MimicsError, match="names: expected one of mimics, stage, got 'ros2'"):
        RosNames("ros2", robots=2)


def test_odom_frame_is_the_start_pose():
    start = np.array([[2.0, 1.0, math.pi / 2], [-1.0, 0.0, 0.0]])
    later = np.array([[2.0, 3.0, math.pi], [0.5, -1.0, 0.25]])
    seen = relative_poses(start, later)
    # robot 0 faced +y and moved 2 m along it, then turned left: 2 m ahead, +90 degrees
    np.testing.assert_allclose(seen[0], [2.0, 0.0, math.pi / 2], atol=1e-12)
    np.testing.assert_allclose(seen[1], [1.5, -1.0, 0.25], atol=1e-12)
    np.testing.assert_array_equal(relative_poses(start, start), np.zeros((2, 3)))


def test_covariance_closed_forms_straight_and_on_the_spot():
    sigma_t, sigma_r = np.array([0.03]), np.array([0.05])
    frames = OdometerFrames(np.array([[0.0, 0.0, 0.0]]), sigma_t, sigma_r)
    for k in range(1, 11):  # ten 0.2 m steps straight ahead
        frames.update(np.array([[0.2 * k, 0.0, 0.0]]))
    # along the heading the variances add up: sigma_t^2 * sum(d^2); nothing across, no turn
    np.testing.assert_allclose(frames.covariance[0], np.diag([0.03**2 * 10 * 0.2**2, 0, 0]),
                               atol=1e-18)
    spin = OdometerFrames(np.array([[1.0, 1.0, 0.0]]), sigma_t, sigma_r)
    for k in range(1, 6):  # five 0.1 rad turns on the spot
        spin.update(np.array([[1.0, 1.0, 0.1 * k]]))
    np.testing.assert_allclose(spin.covariance[0], np.diag([0, 0, 0.05**2 * 5 * 0.1**2]),
                               atol=1e-18)


def test_covariance_matches_the_spread_of_many_noisy_odometers():
    """The first-order covariance against 20000 odometers that draw the engine's noise."""
    rng = np.random.default_rng(7)
    sigma_t, sigma_r = 0.03, 0.05
    steps, samples = 60, 20_000
    distance, turn = 0.08, 0.03  # an arc, the increments of each step
    nominal = np.zeros((1, 3))
    covariance = np.zeros((1, 3, 3))
    odometers = np.zeros((samples, 3))
    for _ in range(steps):
        noisy_distance = distance + rng.standard_normal(samples) * sigma_t * distance
        noisy_turn = turn + rng.standard_normal(samples) * sigma_r * turn
        odometers = advance_pose(odometers, noisy_distance, noisy_turn)
        after = advance_pose(nominal, np.array([distance]), np.array([turn]))
        covariance = propagate(covariance, nominal, after, np.array([sigma_t]),
                               np.array([sigma_r]))
        nominal = after
    spread = np.cov(odometers.T)
    np.testing.assert_allclose(np.diag(covariance[0]), np.diag(spread), rtol=0.06)
    np.testing.assert_allclose(covariance[0], spread, atol=0.06 * np.max(np.diag(spread)))


def test_ros_algorithm_string_takes_the_name_set_before_the_program():
    command = NodeCommand.parse(f"--names=stage {NODE} --robots {{robots}}", Path.cwd())
    assert command.names == "stage" and command.program == NODE
    assert command.args == ("--robots", "{robots}")
    assert NodeCommand.parse(command.text, Path.cwd()) == command  # a battery stores the text
    assert SCHEME.label(f"--names=stage {NODE}") == "ros-stage_user_node"
    assert NodeCommand.parse(str(NODE), Path.cwd()).names is None  # the process's default
    with pytest.raises(AlgorithmError, match="unknown option '--name=stage' before the program"):
        NodeCommand.parse(f"--name=stage {NODE}", Path.cwd())
    with pytest.raises(AlgorithmError, match="--names=: expected one of mimics, stage, got 'x'"):
        NodeCommand.parse(f"--names=x {NODE}", Path.cwd())


def test_a_battery_file_keeps_the_name_set_of_its_ros_algorithm():
    from mimics.batteries.spec import spec_from_dict

    spec = spec_from_dict({"battery": {"algorithms": ["ros:--names=stage nodes/stage_user_node.py"
                                                      " --robots {robots}"]},
                           "scenarios": [{"name": "line", "robots": 2}]},
                          base=NODE.parents[1])
    (algorithm,) = spec.algorithms
    assert algorithm == f"ros:--names=stage {NODE} --robots {{robots}}"  # the program made absolute
    (run,) = spec.runs()
    assert run.algorithm == "ros-stage_user_node"
    _, controller = SCHEME.algorithm(algorithm.removeprefix("ros:"))
    assert controller.command.names == "stage"  # what the worker's bridge is built with
