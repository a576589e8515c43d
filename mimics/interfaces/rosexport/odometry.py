"""nav_msgs/Odometry: each robot's odometer, positioning and ground truth, as the bridge sends them.

One message per row of trajectory.parquet on each topic (names from
:class:`~mimics.interfaces.ros.names.RosNames`), child frame the robot's body
(``base_link``, ``base_footprint`` under the ``stage`` names), the pose's
heading as a rotation about z and the twist along the body's x and about z:

* ``odom``: the odometer rebuilt by :mod:`~.odometer`, in the robot's ``odom``
  frame (``(0, 0, 0)`` at its start pose), with the covariance of
  :mod:`mimics.interfaces.ros.odometry_frame`; the twist is the measured
  velocity (variance ``sigma_velocity**2`` on v and w). Left out when the run
  cannot be rebuilt (:func:`~.odometer.odometer_gap`).
* ``pose`` (``mimics`` names only): the positioning sensor's pose in ``map``
  (variance ``sigma_position**2`` on x and y), twist as ``odom``'s.
* ``ground_truth`` (``base_pose_ground_truth``): the true pose in ``map`` and
  the true velocity, covariance 0.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np

from mimics.engine.state import TypeArrays
from mimics.interfaces.ros.names import MAP_FRAME, RosNames
from mimics.interfaces.ros.planar import covariance_6x6
from mimics.interfaces.rosexport.conversion import Messages, Stamped
from mimics.interfaces.rosexport.odometer import OdometerTrack
from mimics.interfaces.rosexport.source import Trajectory
from mimics.interfaces.rosexport.topics import ODOMETRY

_NONE = np.zeros((3, 3))


def _odometry(messages: Messages, stamp: int, frame: str, child: str, pose: np.ndarray,
              velocity: np.ndarray, covariance: np.ndarray,
              velocity_variance: tuple[float, float]) -> Any:
    twist_covariance = np.zeros(36)
    twist_covariance[0], twist_covariance[35] = velocity_variance
    twist = messages.make(
        "geometry_msgs/msg/Twist",
        linear=messages.make("geometry_msgs/msg/Vector3", x=float(velocity[0])),
        angular=messages.make("geometry_msgs/msg/Vector3", z=float(velocity[1])))
    return messages.make(
        ODOMETRY, header=messages.header(stamp, frame), child_frame_id=child,
        pose=messages.make("geometry_msgs/msg/PoseWithCovariance",
                           pose=messages.pose(*pose),
                           covariance=np.array(covariance_6x6(covariance), dtype=np.float64)),
        twist=messages.make("geometry_msgs/msg/TwistWithCovariance", twist=twist,
                            covariance=twist_covariance))


def odometry_messages(messages: Messages, trajectory: Trajectory, names: RosNames,
                      types: TypeArrays, odometer: OdometerTrack | None,
                      velocity: np.ndarray | None) -> Iterator[Stamped]:
    """Per trajectory row, in (step, robot) order: ``odom`` (when ``odometer`` is given),
    ``pose`` (when the name set has it) and the ground truth. ``velocity`` is the
    measured velocity of each row (None, unknown: no ``odom`` nor ``pose``)."""
    velocity_variance = [(float(s) ** 2,) * 2 for s in types.sigma_velocity]
    position_covariance = [np.diag([float(s) ** 2] * 2 + [0.0]) for s in types.sigma_position]
    true_pose = np.column_stack((trajectory.x, trajectory.y, trajectory.theta))
    measured_pose = np.column_stack((trajectory.x_meas, trajectory.y_meas, trajectory.theta_meas))
    true_velocity = np.column_stack((trajectory.v, trajectory.w))
    for k in range(trajectory.rows):
        robot, stamp = int(trajectory.robot[k]), int(trajectory.stamp[k])
        body = names.body_frame(robot)
        if velocity is not None and odometer is not None:
            yield Stamped(stamp, names.odom(robot), _odometry(
                messages, stamp, names.odom_frame(robot), body, odometer.pose[k], velocity[k],
                odometer.covariance[k], velocity_variance[robot]))
        pose_topic = names.pose(robot)
        if velocity is not None and pose_topic is not None:
            yield Stamped(stamp, pose_topic, _odometry(
                messages, stamp, MAP_FRAME, body, measured_pose[k], velocity[k],
                position_covariance[robot], velocity_variance[robot]))
        yield Stamped(stamp, names.ground_truth(robot), _odometry(
            messages, stamp, MAP_FRAME, body, true_pose[k], true_velocity[k], _NONE, (0.0, 0.0)))
