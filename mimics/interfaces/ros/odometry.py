"""Each active robot's odometry, positioning and ground truth, as ``nav_msgs/Odometry``.

* ``odom`` (both name sets): the odometer's pose in the robot's ``odom``
  frame (its start pose: ``(0, 0, 0)`` at ``t = 0``), with its accumulated
  noise and the covariance of :mod:`~mimics.interfaces.ros.odometry_frame`;
  the twist is the measured velocity (variance ``sigma_velocity**2`` on v and w).
* ``pose`` (``mimics`` names only): the positioning sensor's measured pose
  in ``map`` (variance ``sigma_position**2`` on x and y) and the measured velocity,
  what mimics' own algorithms read as ``robot.pose``.
* ``ground_truth`` / ``base_pose_ground_truth``: the true pose in ``map``
  and the true velocity, covariance 0.

The child frame is the robot's body (``base_link``, or ``base_footprint``
under the ``stage`` names). All three are latched (see ``bridge``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import rospy
from nav_msgs.msg import Odometry

from mimics.interfaces.ros.conversion import odometry_message
from mimics.interfaces.ros.names import MAP_FRAME, RosNames
from mimics.interfaces.ros.odometry_frame import OdometerFrames

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation

_NO_COVARIANCE = np.zeros((3, 3))


def _latched(topic: str) -> rospy.Publisher:
    return rospy.Publisher(topic, Odometry, queue_size=10, tcp_nodelay=True, latch=True)


class OdometryPublisher:
    """Publishes every robot's ``odom``, ``pose`` (when the name set has it) and ground truth."""

    def __init__(self, sim: Simulation, names: RosNames) -> None:
        n, types = sim.state.n, sim.types
        self.names = names
        # the odometer starts at the start pose (the engine copies the pose into it)
        self.frames = OdometerFrames(sim.state.odometry, types.sigma_translation,
                                     types.sigma_rotation)
        self.publishers = [_latched(names.odom(i)) for i in range(n)]
        pose_topics = [names.pose(i) for i in range(n)]
        self.pose_publishers = [_latched(topic) for topic in pose_topics if topic is not None]
        self.truth_publishers = [_latched(names.ground_truth(i)) for i in range(n)]

    def all_publishers(self, robot: int) -> list[rospy.Publisher]:
        """The robot's publishers (a node listening to any of them is connected)."""
        own = [self.publishers[robot], self.truth_publishers[robot]]
        return own + ([self.pose_publishers[robot]] if self.pose_publishers else [])

    def publish(self, sim: Simulation, ids: np.ndarray) -> None:
        """The odometer, measured pose and true pose of robots ``ids`` at the current step."""
        state, types, names = sim.state, sim.types, self.names
        if state.step > 0:  # step 0: the odometer is at its start, covariance 0
            self.frames.update(state.odometry)
        seconds = state.time
        for i in ids.tolist():
            body = names.body_frame(i)
            velocity_variance = (float(types.sigma_velocity[i]) ** 2,) * 2
            self.publishers[i].publish(odometry_message(
                seconds, names.odom_frame(i), body, self.frames.pose[i],
                state.measured_velocity[i], self.frames.covariance[i], velocity_variance))
            if self.pose_publishers:
                position_variance = float(types.sigma_position[i]) ** 2
                self.pose_publishers[i].publish(odometry_message(
                    seconds, MAP_FRAME, body, state.measured_pose[i], state.measured_velocity[i],
                    np.diag([position_variance, position_variance, 0.0]), velocity_variance))
            self.truth_publishers[i].publish(odometry_message(
                seconds, MAP_FRAME, body, state.pose[i], state.velocity[i], _NO_COVARIANCE,
                (0.0, 0.0)))

    def close(self) -> None:
        """Withdraw the topics."""
        for publisher in (*self.publishers, *self.pose_publishers, *self.truth_publishers):
            publisher.unregister()
