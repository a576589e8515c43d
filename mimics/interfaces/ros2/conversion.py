"""mimics' arrays as ROS 2 messages (:mod:`.messages`), and ``cmd_vel`` back as a command.

What the values mean (stamps, quaternions, covariances, the ``map -> odom``
correction, scan values, the command's checks) is the ROS 1 bridge's,
computed once in :mod:`mimics.interfaces.ros.planar` and
:mod:`mimics.interfaces.ros.readings`: only the message classes differ.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from mimics.interfaces.ros import planar
from mimics.interfaces.ros.inbox import Command
from mimics.interfaces.ros.names import MAP_FRAME
from mimics.interfaces.ros.occupancy import Grid
from mimics.interfaces.ros.readings import Reading
from mimics.interfaces.ros2 import messages as msg
from mimics.interfaces.rosexport.pieces import MessagePieces


def time(seconds: float) -> msg.Time:
    """Simulated seconds as ``builtin_interfaces/Time``."""
    return msg.Time(*planar.sec_nanosec(seconds))


def header(seconds: float, frame_id: str) -> msg.Header:
    """A header stamped with simulated time (ROS 2's has no ``seq``)."""
    return msg.Header(stamp=time(seconds), frame_id=frame_id)


def quaternion(yaw: float) -> msg.Quaternion:
    """A rotation of ``yaw`` radians about z."""
    return msg.Quaternion(*planar.yaw_quaternion(yaw))


def pose(x: float, y: float, yaw: float) -> msg.Pose:
    """A planar pose."""
    return msg.Pose(msg.Point(float(x), float(y), 0.0), quaternion(yaw))


def odometry(seconds: float, frame_id: str, child_frame_id: str,
             reading: Reading) -> msg.Odometry:
    """A planar pose in ``frame_id`` and a velocity in ``child_frame_id`` (see
    :func:`mimics.interfaces.ros.conversion.odometry_message`)."""
    x, y, theta = (float(value) for value in reading.pose)
    speed, turn = (float(value) for value in reading.velocity)
    twist_covariance = [0.0] * 36
    twist_covariance[0], twist_covariance[35] = reading.variance
    return msg.Odometry(
        header=header(seconds, frame_id), child_frame_id=child_frame_id,
        pose=msg.PoseWithCovariance(pose(x, y, theta),
                                    planar.covariance_6x6(reading.covariance)),
        twist=msg.TwistWithCovariance(msg.Twist(msg.Vector3(speed, 0.0, 0.0),
                                                msg.Vector3(0.0, 0.0, turn)),
                                      twist_covariance))


def scan(frame_id: str, seconds: float, ranges: np.ndarray, hit: np.ndarray,
         angles: np.ndarray, max_range: float, dt: float,
         no_return_at_max: bool = False, intensities: bool = False) -> msg.LaserScan:
    """One ranger reading (see :func:`mimics.interfaces.ros.planar.scan_values`);
    ``intensities``: stage_ros' (:func:`~mimics.interfaces.ros.planar.scan_intensities`),
    else none."""
    angle_min, angle_max, increment, values = planar.scan_values(ranges, hit, angles,
                                                                 max_range, no_return_at_max)
    strengths = planar.scan_intensities(hit).tolist() if intensities else []
    return msg.LaserScan(header(seconds, frame_id), angle_min, angle_max, increment, 0.0,
                         float(dt), 0.0, float(max_range), values.tolist(), strengths)


def goal(seconds: float, target: np.ndarray) -> msg.PoseStamped:
    """A robot's goal as a pose in ``map`` (no orientation: identity)."""
    return msg.PoseStamped(header(seconds, MAP_FRAME), pose(target[0], target[1], 0.0))


def grid(cells: Grid, seconds: float) -> msg.OccupancyGrid:
    """An occupancy grid: 100 on cells that walls cross, 0 elsewhere, row 0 at the bottom."""
    info = msg.MapMetaData(time(seconds), cells.resolution, cells.width, cells.height,
                           pose(cells.origin[0], cells.origin[1], 0.0))
    return msg.OccupancyGrid(header(seconds, MAP_FRAME), info, cells.cells.ravel().tolist())


def transform(seconds: float, parent: str, child: str, x: float, y: float,
              yaw: float) -> msg.TransformStamped:
    """The planar pose of ``child`` in ``parent``."""
    return msg.TransformStamped(header(seconds, parent), child,
                                msg.Transform(msg.Vector3(float(x), float(y), 0.0),
                                              quaternion(yaw)))


def odometry_transforms(seconds: float, odom_frame: str, body_frame: str, measured: np.ndarray,
                        odometer: np.ndarray,
                        map_odom: bool = True) -> list[msg.TransformStamped]:
    """``map -> odom -> body`` for one robot (REP 105; see
    :func:`mimics.interfaces.ros.planar.odom_correction`); ``odom -> body`` only
    without ``map_odom``."""
    ox, oy, otheta = (float(value) for value in odometer)
    to_body = transform(seconds, odom_frame, body_frame, ox, oy, otheta)
    if not map_odom:
        return [to_body]
    return [transform(seconds, MAP_FRAME, odom_frame,
                      *planar.odom_correction(measured, odometer)), to_body]


def clock(seconds: float) -> msg.Clock:
    """``/clock`` at simulated time."""
    return msg.Clock(time(seconds))


def command_from_array(message: msg.Float64MultiArray, dt: float) -> Command:
    """``cmd``: ``data = [speed_ref, heading_ref(, stamp)]`` (see
    :func:`mimics.interfaces.ros.planar.array_command`).

    Raises:
        BadCommand: on a wrong length or a value that is not finite.
    """
    return planar.array_command(list(message.data), dt)


def command_from_twist(message: msg.Twist) -> Command:
    """``cmd_vel``: ``linear.x`` (m/s) and ``angular.z`` (rad/s); the rest is ignored.

    Raises:
        BadCommand: when either is not finite.
    """
    return planar.twist_command(message.linear.x, message.angular.z)


class IdlMessages(MessagePieces):
    """The marker builders' message factory with these IDL classes."""

    def make(self, msgtype: str, **fields: Any) -> Any:
        """``make("geometry_msgs/msg/Point", x=1.0)`` gives ``messages.Point(x=1.0)``."""
        return msg.BY_NAME[msgtype](**fields)

    def stamp(self, nanoseconds: int) -> msg.Time:
        """A ``builtin_interfaces/Time`` of whole nanoseconds."""
        sec, nanosec = divmod(int(nanoseconds), 1_000_000_000)
        return msg.Time(sec, nanosec)
