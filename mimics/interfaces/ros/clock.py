"""``/clock``: the simulated time, once per step (nodes with ``use_sim_time`` follow it)."""

from __future__ import annotations

import rospy
from rosgraph_msgs.msg import Clock

from mimics.interfaces.ros.conversion import clock_message


class ClockPublisher:
    """Publishes ``rosgraph_msgs/Clock`` on ``/clock``."""

    def __init__(self) -> None:
        self._publisher = rospy.Publisher("/clock", Clock, queue_size=10)

    def publish(self, seconds: float) -> None:
        """Announce simulated time ``seconds``."""
        self._publisher.publish(clock_message(seconds))

    def close(self) -> None:
        """Withdraw the topic."""
        self._publisher.unregister()
