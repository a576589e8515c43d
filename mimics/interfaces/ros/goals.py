"""Each robot's goal (``/robot_i/goal``; ``/goal`` for a single robot under the ``stage``
names), latched; robots without a goal publish none."""

from __future__ import annotations

import numpy as np
import rospy
from geometry_msgs.msg import PoseStamped

from mimics.interfaces.ros.conversion import goal_message
from mimics.interfaces.ros.names import RosNames


class GoalPublisher:
    """Latches ``geometry_msgs/PoseStamped`` goals, in ``map``, once."""

    def __init__(self, goals: np.ndarray, names: RosNames) -> None:
        self.publishers = []
        for i, goal in enumerate(goals):
            if not np.all(np.isfinite(goal)):
                continue
            publisher = rospy.Publisher(names.goal(i), PoseStamped,
                                        queue_size=1, latch=True)
            publisher.publish(goal_message(0.0, goal))
            self.publishers.append(publisher)

    def close(self) -> None:
        """Withdraw the topics."""
        for publisher in self.publishers:
            publisher.unregister()
