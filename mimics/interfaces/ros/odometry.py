"""``/robot_i/odom``: each active robot's measured (noisy) pose and velocity."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import rospy
from nav_msgs.msg import Odometry

from mimics.interfaces.ros.conversion import odometry_message, robot_namespace

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation


class OdometryPublisher:
    """Publishes ``nav_msgs/Odometry`` for every robot, pose in ``map``."""

    def __init__(self, robots: int) -> None:
        self.publishers = [rospy.Publisher(f"/{robot_namespace(i)}/odom", Odometry,
                                           queue_size=10, tcp_nodelay=True,
                                           latch=True)
                           for i in range(robots)]

    def publish(self, sim: Simulation, ids: np.ndarray) -> None:
        """The measured pose and velocity of robots ``ids`` at the current step."""
        state, types = sim.state, sim.types
        for i in ids.tolist():
            self.publishers[i].publish(odometry_message(
                i, state.time, state.measured_pose[i], state.measured_velocity[i],
                float(types.sigma_position[i]), float(types.sigma_velocity[i])))

    def close(self) -> None:
        """Withdraw the topics."""
        for publisher in self.publishers:
            publisher.unregister()
