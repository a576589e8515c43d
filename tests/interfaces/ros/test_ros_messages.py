"""Message conversion (needs ROS's Python message packages, no master)."""

from __future__ import annotations

import math
from types import ModuleType
from typing import Any

import numpy as np
import pytest

from mimics.engine.simulation import Simulation
from mimics.interfaces.ros.inbox import Command
from mimics.interfaces.ros.occupancy import rasterise
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_3AT, PidGains, RobotType
from mimics.world.scenario import Scenario, Settings
from tests.system_packages import require


@pytest.fixture(scope="module")
def convert() -> ModuleType:
    """The conversion module, once ROS's message packages are importable."""
    require("ros")
    from mimics.interfaces.ros.system_ros import require_ros

    require_ros()
    from mimics.interfaces.ros import conversion

    return conversion


def float64_array(data: list[float]) -> Any:
    from std_msgs.msg import Float64MultiArray

    return Float64MultiArray(data=data)


def planar(x: float, y: float, yaw: float) -> np.ndarray:
    return np.array([[math.cos(yaw), -math.sin(yaw), x], [math.sin(yaw), math.cos(yaw), y],
                     [0.0, 0.0, 1.0]])


def as_matrix(transform: Any) -> np.ndarray:
    t = transform.transform
    yaw = math.atan2(2.0 * t.rotation.w * t.rotation.z, 1.0 - 2.0 * t.rotation.z**2)
    return planar(t.translation.x, t.translation.y, yaw)


@pytest.mark.parametrize("yaw", [0.0, 0.3, -2.0, math.pi - 1e-9, 3 * math.pi / 2])
def test_quaternion_round_trip(convert, yaw):
    q = convert.yaw_quaternion(yaw)
    assert q.x**2 + q.y**2 + q.z**2 + q.w**2 == pytest.approx(1.0)
    back = convert.quaternion_yaw(q)
    assert math.cos(back - yaw) == pytest.approx(1.0) and math.sin(back - yaw) == pytest.approx(
        0.0, abs=1e-12)


def test_stamps_are_exact_nanoseconds_and_map_back_to_steps(convert):
    assert convert.stamp(0.3).to_nsec() == 300_000_000
    assert convert.stamp(21.7).to_nsec() == 21_700_000_000
    assert convert.step_of(convert.stamp(0.1 * 217).to_sec(), 0.1) == 217


def test_frames_chain_to_the_measured_pose(convert):
    pose, odometry = np.array([3.0, -1.5, 2.5]), np.array([2.7, -1.2, 2.3])
    to_odom, to_base = convert.odometry_transforms(1.2, "robot_4/odom", "robot_4/base_link",
                                                   pose, odometry)
    assert (to_odom.header.frame_id, to_odom.child_frame_id) == ("map", "robot_4/odom")
    assert (to_base.header.frame_id, to_base.child_frame_id) == ("robot_4/odom",
                                                                 "robot_4/base_link")
    np.testing.assert_allclose(as_matrix(to_base), planar(*odometry), atol=1e-12)
    np.testing.assert_allclose(as_matrix(to_odom) @ as_matrix(to_base), planar(*pose),
                               atol=1e-12)
    laser = convert.fixed_transform("robot_4/base_link", "robot_4/laser")
    assert (laser.header.frame_id, laser.child_frame_id) == ("robot_4/base_link",
                                                             "robot_4/laser")
    np.testing.assert_allclose(as_matrix(laser), np.eye(3), atol=1e-12)


def test_odometry_carries_pose_velocity_and_covariances(convert):
    covariance = np.array([[0.01, 0.002, 0.003], [0.002, 0.02, 0.004], [0.003, 0.004, 0.03]])
    message = convert.odometry_message(0.5, "robot_2/odom", "robot_2/base_link",
                                       np.array([1.0, 2.0, 0.7]), np.array([0.4, -0.1]),
                                       covariance, (0.0004, 0.0009))
    assert (message.header.frame_id, message.child_frame_id) == ("robot_2/odom",
                                                                 "robot_2/base_link")
    assert message.header.stamp.to_nsec() == 500_000_000
    p = message.pose.pose
    assert (p.position.x, p.position.y) == (1.0, 2.0)
    assert convert.quaternion_yaw(p.orientation) == pytest.approx(0.7)
    assert (message.twist.twist.linear.x, message.twist.twist.angular.z) == (0.4, -0.1)
    # row-major 6x6 over x, y, z, roll, pitch, yaw: x, y, yaw are rows/columns 0, 1, 5
    full = np.array(message.pose.covariance).reshape(6, 6)
    np.testing.assert_array_equal(full[np.ix_([0, 1, 5], [0, 1, 5])], covariance)
    assert np.count_nonzero(full) == 9
    assert message.twist.covariance[0] == 0.0004 and message.twist.covariance[35] == 0.0009


def test_a_refilled_odometry_message_is_a_fresh_one(convert):
    import io

    def serialised(message):
        buffer = io.BytesIO()
        message.serialize(buffer)
        return buffer.getvalue()

    first = (0.1, np.array([1.0, 2.0, 0.7]), np.array([0.4, -0.1]), np.eye(3), (0.1, 0.2))
    second = (0.2, np.array([-3.0, 0.5, -2.9]), np.array([0.0, 0.3]),
              np.arange(9.0).reshape(3, 3), (0.0, 0.0))
    reused = convert.odometry_message(first[0], "odom", "base_footprint", *first[1:])
    convert.fill_odometry(reused, *second)
    fresh = convert.odometry_message(second[0], "odom", "base_footprint", *second[1:])
    assert serialised(reused) == serialised(fresh)


def test_scan_has_the_rangers_angles_and_inf_for_no_return(convert):
    offsets = np.array(PIONEER_3AT.ranger.beam_offsets())
    ranges = np.full(offsets.shape, 30.0)
    hit = np.zeros(offsets.shape, dtype=bool)
    ranges[10], hit[10] = 4.25, True
    message = convert.scan_message("robot_0/laser", 0.1, ranges, hit, offsets, 30.0, 0.1)
    assert message.header.frame_id == "robot_0/laser"
    assert message.angle_min == pytest.approx(-math.radians(135))
    assert message.angle_max == pytest.approx(math.radians(135))
    # LaserScan's beams are angle_min + k * angle_increment
    np.testing.assert_allclose(message.angle_min + np.arange(270) * message.angle_increment,
                               offsets, atol=1e-12)
    assert message.range_max == 30.0
    assert message.ranges[10] == 4.25
    assert sum(math.isinf(r) for r in message.ranges) == 269
    # stage_ros' habit (the stage names): no return reads range_max, returns unchanged
    staged = convert.scan_message("base_laser_link", 0.1, ranges, hit, offsets, 30.0, 0.1,
                                  no_return_at_max=True)
    assert staged.ranges[10] == 4.25
    assert [r for k, r in enumerate(staged.ranges) if k != 10] == [30.0] * 269


def test_grid_message_is_row_major_from_the_lower_left_corner(convert):
    grid = rasterise(Map([[0.05, 0.35, 0.05, 0.38]], (-1.0, 0.0, 1.0, 1.0)), 0.1)
    message = convert.grid_message(grid, 0.0)
    info = message.info
    assert (info.width, info.height, info.resolution) == (20, 10, pytest.approx(0.1))
    assert (info.origin.position.x, info.origin.position.y) == (-1.0, 0.0)
    occupied = [k for k, value in enumerate(message.data) if value == 100]
    assert occupied == [3 * 20 + 10]  # row 3 (y 0.3 to 0.4), column 10 (x 0.0 to 0.1)


def test_cmd_arrays(convert):
    plain = convert.command_from_array(float64_array([0.5, -1.0]), 0.1)
    assert plain == Command("reference", 0.5, -1.0, None)
    stamped = convert.command_from_array(float64_array([0.5, -1.0, 0.30000000004]),
                                         0.1)
    assert stamped.step == 3


@pytest.mark.parametrize(("data", "problem"), [
    ([0.5], "got 1 values"), ([0.5, 1.0, 0.2, 9.0], "got 4 values"),
    ([math.nan, 1.0], "speed_ref must be a finite number, got nan"),
    ([0.5, math.inf], "heading_ref must be a finite number, got inf"),
    ([0.5, 1.0, -0.3], "stamp must not be negative")])
def test_bad_cmd_arrays(convert, data, problem):
    with pytest.raises(convert.BadCommand, match=problem):
        convert.command_from_array(float64_array(data), 0.1)


def test_twists(convert):
    from geometry_msgs.msg import Twist

    twist = Twist()
    twist.linear.x, twist.angular.z = 0.3, -0.4
    assert convert.command_from_twist(twist) == Command("twist", 0.3, -0.4, None)
    twist.angular.z = math.nan
    with pytest.raises(convert.BadCommand, match=r"angular\.z"):
        convert.command_from_twist(twist)


@pytest.mark.parametrize(("kw", "gains", "rate"), [
    (1.0, PidGains(kp=2.0, ki=0.0, kd=0.1), 0.5),  # the built-in types' heading loop
    (0.8, PidGains(kp=1.5, ki=0.0, kd=0.3), -0.6)])
def test_a_twist_turns_the_robot_at_the_commanded_rate(convert, kw, gains, rate):
    kind = RobotType(name="turner", width=0.4, length=0.5, kv=1.0, kw=kw, tau_v=0.3, tau_w=0.2,
                     heading_pid=gains)
    world = Scenario.from_matrix([[0.0, 0.0, 0.0, 0.0]], Map.empty((-50, -50, 50, 50)), kind,
                                 settings=Settings(time_limit=4.0))

    def step(robot):
        return convert.twist_to_references(0.2, rate, float(robot.heading), kw, gains.kp,
                                           gains.kd)

    sim = Simulation(world, step)
    sim.run()
    # the dynamics, run by the engine, settle on the commanded rate and speed reference
    assert sim.state.velocity[0, 1] == pytest.approx(rate, rel=1e-3)
    assert sim.state.reference[0, 0] == 0.2
