"""Every conversion between mimics' arrays and ROS messages, in one place.

Outgoing: odometry, laser scans, goals, the occupancy grid, tf2 transforms
and the clock, all stamped with simulated time. Incoming: the two command
messages, checked and turned into :class:`~mimics.interfaces.ros.inbox.Command`.

Frame and topic names come from :mod:`~mimics.interfaces.ros.names` (the
``mimics`` or the ``stage`` name set); the functions here take frame ids.
What the messages mean (stamps, quaternions, covariances, the ``map -> odom``
correction, scan values, command checks) is computed in
:mod:`~mimics.interfaces.ros.planar`, which the ROS 2 bridge shares.
"""

from __future__ import annotations

import math

import numpy as np
import rospy
from geometry_msgs.msg import PoseStamped, Quaternion, TransformStamped, Twist
from nav_msgs.msg import OccupancyGrid, Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Float64MultiArray, Header

from mimics.interfaces.ros import planar
from mimics.interfaces.ros.inbox import Command
from mimics.interfaces.ros.names import MAP_FRAME
from mimics.interfaces.ros.occupancy import Grid
from mimics.interfaces.ros.planar import (  # re-exported: the ROS 1 modules import them here
    PLANAR,
    BadCommand,
    quaternion_yaw,
    step_of,
    twist_to_references,
)

__all__ = ["PLANAR", "BadCommand", "quaternion_yaw", "step_of", "twist_to_references"]


def stamp(seconds: float) -> rospy.Time:
    """Simulated seconds as a ROS time, rounded to the nanosecond (no float truncation)."""
    return rospy.Time(nsecs=planar.nanoseconds(seconds))


def yaw_quaternion(yaw: float) -> Quaternion:
    """A rotation of ``yaw`` radians about z."""
    return Quaternion(*planar.yaw_quaternion(yaw))


def header(seconds: float, frame_id: str) -> Header:
    """A header stamped with simulated time."""
    return Header(stamp=stamp(seconds), frame_id=frame_id)


def odometry_message(seconds: float, frame_id: str, child_frame_id: str, pose: np.ndarray,
                     velocity: np.ndarray, pose_covariance: np.ndarray,
                     velocity_variance: tuple[float, float]) -> Odometry:
    """A planar pose in ``frame_id`` and a velocity in ``child_frame_id``.

    ``pose`` is ``(x, y, theta)``, ``velocity`` ``(v, w)``; ``pose_covariance``
    is the 3x3 covariance of ``(x, y, theta)``, written into the message's
    6x6 (rows and columns x, y and yaw: 0, 1 and 5); ``velocity_variance``
    the variances of ``v`` and ``w`` (twist rows 0 and 5). The dimensions a
    planar robot does not have (z, roll, pitch) get 0.
    """
    message = Odometry(header=Header(frame_id=frame_id), child_frame_id=child_frame_id)
    message.pose.covariance = [0.0] * 36
    message.twist.covariance = [0.0] * 36
    fill_odometry(message, seconds, pose, velocity, pose_covariance, velocity_variance)
    return message


def fill_odometry(message: Odometry, seconds: float, pose: np.ndarray, velocity: np.ndarray,
                  pose_covariance: np.ndarray, velocity_variance: tuple[float, float]) -> None:
    """Write a new step into a message of :func:`odometry_message`, in place.

    A sixth of the cost of a new message (6 against 35 us here): the bridge
    keeps one message per robot and topic.
    """
    x, y, theta = pose.tolist()
    message.header.stamp = stamp(seconds)
    position, orientation = message.pose.pose.position, message.pose.pose.orientation
    position.x, position.y = x, y
    orientation.z, orientation.w = math.sin(theta / 2.0), math.cos(theta / 2.0)
    covariance = message.pose.covariance
    for row, values in zip(PLANAR, pose_covariance.tolist(), strict=True):
        for column, value in zip(PLANAR, values, strict=True):
            covariance[6 * row + column] = value
    message.twist.twist.linear.x, message.twist.twist.angular.z = velocity.tolist()
    message.twist.covariance[0], message.twist.covariance[35] = velocity_variance


def scan_message(frame_id: str, seconds: float, ranges: np.ndarray, hit: np.ndarray,
                 angles: np.ndarray, max_range: float, dt: float,
                 no_return_at_max: bool = False, intensities: bool = False) -> LaserScan:
    """One ranger reading; beams that hit nothing read ``+inf`` (REP 117), or
    ``range_max`` with ``no_return_at_max`` (what stage_ros publishes).

    ``angles`` are the ranger's beam angles (right to left, evenly spread),
    ``ranges`` its distances and ``hit`` which beams hit something.
    ``intensities``: filled as stage_ros fills them (1.0 where a beam hit
    something, 0.0 where not: :func:`~mimics.interfaces.ros.planar.scan_intensities`),
    else empty.
    """
    angle_min, angle_max, increment, values = planar.scan_values(ranges, hit, angles,
                                                                 max_range, no_return_at_max)
    return LaserScan(header=header(seconds, frame_id),
                     angle_min=angle_min, angle_max=angle_max, angle_increment=increment,
                     time_increment=0.0, scan_time=dt,
                     range_min=0.0, range_max=float(max_range), ranges=values.tolist(),
                     intensities=planar.scan_intensities(hit).tolist() if intensities else [])


def goal_message(seconds: float, goal: np.ndarray) -> PoseStamped:
    """A robot's goal as a pose in ``map`` (no orientation: identity)."""
    message = PoseStamped(header=header(seconds, MAP_FRAME))
    message.pose.position.x, message.pose.position.y = float(goal[0]), float(goal[1])
    message.pose.orientation.w = 1.0
    return message


def grid_message(grid: Grid, seconds: float) -> OccupancyGrid:
    """An occupancy grid: 100 on cells that walls cross, 0 elsewhere, row 0 at the bottom."""
    message = OccupancyGrid(header=header(seconds, MAP_FRAME))
    info = message.info
    info.map_load_time = stamp(seconds)
    info.resolution = grid.resolution
    info.width, info.height = grid.width, grid.height
    info.origin.position.x, info.origin.position.y = grid.origin
    info.origin.orientation.w = 1.0
    message.data = grid.cells.ravel().tolist()
    return message


def transform(seconds: float, parent: str, child: str, x: float, y: float,
              yaw: float) -> TransformStamped:
    """The planar pose of ``child`` in ``parent``."""
    message = TransformStamped(header=header(seconds, parent), child_frame_id=child)
    message.transform.translation.x, message.transform.translation.y = x, y
    message.transform.rotation = yaw_quaternion(yaw)
    return message


def odometry_transforms(seconds: float, odom_frame: str, body_frame: str, pose: np.ndarray,
                         odometry: np.ndarray, map_odom: bool = True) -> list[TransformStamped]:
    """``map -> odom -> body`` for one robot (REP 105); ``odom -> body`` only without
    ``map_odom``.

    ``odometry`` is the odometer's pose in ``odom_frame``, ``pose`` the
    measured pose in ``map``: ``odom -> body`` is the odometer's estimate;
    ``map -> odom`` is the correction that puts ``body`` at ``pose`` in
    ``map``, ``T(pose) * T(odometry)^-1``, as a localiser would publish it.
    """
    ox, oy, otheta = (float(value) for value in odometry)
    to_body = transform(seconds, odom_frame, body_frame, ox, oy, otheta)
    if not map_odom:
        return [to_body]
    to_odom = transform(seconds, MAP_FRAME, odom_frame, *planar.odom_correction(pose, odometry))
    return [to_odom, to_body]


def fixed_transform(parent: str, child: str) -> TransformStamped:
    """``parent -> child`` as the identity: the laser sits at the robot's centre, facing
    forward, and ``base_link`` on ``base_footprint`` (a planar robot)."""
    return transform(0.0, parent, child, 0.0, 0.0, 0.0)


def clock_message(seconds: float) -> Clock:
    """``/clock`` at simulated time."""
    return Clock(clock=stamp(seconds))


def command_from_array(message: Float64MultiArray, dt: float) -> Command:
    """``cmd``: ``data = [speed_ref, heading_ref]`` or ``[speed_ref, heading_ref, stamp]``.

    ``speed_ref`` in m/s, ``heading_ref`` an absolute heading in ``map`` (rad);
    ``stamp`` is the ``header.stamp`` (in seconds) of the ``odom`` message the
    reference answers, which ties it to that step in lockstep mode.

    Raises:
        BadCommand: on a wrong length or a value that is not finite.
    """
    return planar.array_command(list(message.data), dt)


def command_from_twist(message: Twist) -> Command:
    """``cmd_vel``: ``linear.x`` (m/s) and ``angular.z`` (rad/s); the other fields are ignored.

    Raises:
        BadCommand: when either is not finite.
    """
    return planar.twist_command(message.linear.x, message.angular.z)

