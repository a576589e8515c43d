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
under the ``stage`` names). All three are latched (see ``bridge``). Under
the ``stage`` names a robot that stopped (goal reached, collided) goes on
publishing them, still (zero twist), and :class:`StallPublisher` publishes
each robot's ``is_crashed`` (``std_msgs/Int8``, Stage's stall flag of the step).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import rospy
from nav_msgs.msg import Odometry
from std_msgs.msg import Int8

from mimics.interfaces.ros.conversion import fill_odometry, odometry_message
from mimics.interfaces.ros.names import MAP_FRAME, RosNames
from mimics.interfaces.ros.readings import NO_COVARIANCE, OdometryReadings, Reading, stalled

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation


class _Topic:
    """One robot's latched Odometry topic and the message it sends again each step."""

    def __init__(self, topic: str, frame_id: str, child_frame_id: str) -> None:
        self.publisher = rospy.Publisher(topic, Odometry, queue_size=10, tcp_nodelay=True,
                                         latch=True)
        self.message = odometry_message(0.0, frame_id, child_frame_id, np.zeros(3),
                                        np.zeros(2), NO_COVARIANCE, (0.0, 0.0))

    def send(self, seconds: float, reading: Reading) -> None:
        """Publish the step. The message is filled under the topic's lock, which rospy
        also takes to send the latched message to a subscriber that connects: never
        half-written."""
        impl = self.publisher.impl
        impl.acquire()
        try:
            fill_odometry(self.message, seconds, *reading)
            self.publisher.publish(self.message)
        finally:
            impl.release()


class OdometryPublisher:
    """Publishes every robot's ``odom``, ``pose`` (when the name set has it) and ground truth."""

    def __init__(self, sim: Simulation, names: RosNames) -> None:
        n = sim.state.n
        self.names = names
        self.readings = OdometryReadings(sim)  # what each topic carries (shared with ROS 2)
        self.frames = self.readings.frames
        self.odom = [_Topic(names.odom(i), names.odom_frame(i), names.body_frame(i))
                     for i in range(n)]
        self.pose = [_Topic(topic, MAP_FRAME, names.body_frame(i))
                     for i in range(n) if (topic := names.pose(i)) is not None]
        self.truth = [_Topic(names.ground_truth(i), MAP_FRAME, names.body_frame(i))
                      for i in range(n)]

    def all_publishers(self, robot: int) -> list[rospy.Publisher]:
        """The robot's publishers (a node listening to any of them is connected)."""
        topics = [self.odom[robot], self.truth[robot]]
        return [topic.publisher for topic in topics + self.pose[robot:robot + 1]]

    def publish(self, sim: Simulation, ids: np.ndarray) -> None:
        """The odometer, measured pose and true pose of robots ``ids`` at the current step."""
        readings, seconds = self.readings, sim.state.time
        readings.update(sim)
        for i in ids.tolist():
            self.odom[i].send(seconds, readings.odom(sim, i))
            if self.pose:
                self.pose[i].send(seconds, readings.pose(sim, i))
            self.truth[i].send(seconds, readings.truth(sim, i))

    def close(self) -> None:
        """Withdraw the topics."""
        for topic in (*self.odom, *self.pose, *self.truth):
            topic.publisher.unregister()


class StallPublisher:
    """Publishes each robot's ``is_crashed`` (``std_msgs/Int8``: 1 while stalled against a
    wall or a robot, see :func:`~mimics.interfaces.ros.readings.stalled`, else 0) every
    step, latched, when the name set has the topic (``stage``)."""

    def __init__(self, n: int, names: RosNames) -> None:
        topics = [names.stall(i) for i in range(n)]
        self.publishers = {i: rospy.Publisher(topic, Int8, queue_size=10, latch=True)
                           for i, topic in enumerate(topics) if topic is not None}

    def publish(self, sim: Simulation, ids: np.ndarray) -> None:
        """The stall flags of robots ``ids`` at the current step."""
        if not self.publishers:
            return
        flags = stalled(sim.state)
        for i in ids.tolist():
            self.publishers[i].publish(Int8(data=int(flags[i])))

    def close(self) -> None:
        """Withdraw the topics."""
        for publisher in self.publishers.values():
            publisher.unregister()
