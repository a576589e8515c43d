"""tf2 frames: ``map -> robot_i/odom -> robot_i/base_link`` on ``/tf`` every step, and
``robot_i/base_link -> robot_i/laser`` once on the latched ``/tf_static``.

Published as plain ``tf2_msgs/TFMessage`` (what ``tf2_ros``' broadcasters
send), so no compiled part of tf2 is loaded.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import rospy
from tf2_msgs.msg import TFMessage

from mimics.interfaces.ros.conversion import laser_transform, robot_transforms

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation


class FramePublisher:
    """Broadcasts every robot's frames."""

    def __init__(self, beam_count: np.ndarray) -> None:
        self._dynamic = rospy.Publisher("/tf", TFMessage, queue_size=100)
        self._static = rospy.Publisher("/tf_static", TFMessage, queue_size=1, latch=True)
        lasers = [laser_transform(i) for i in np.flatnonzero(beam_count > 0).tolist()]
        self._static.publish(TFMessage(transforms=lasers))

    def publish(self, sim: Simulation, ids: np.ndarray) -> None:
        """The frames of robots ``ids`` at the current step, in one message."""
        state = sim.state
        transforms = []
        for i in ids.tolist():
            transforms.extend(robot_transforms(i, state.time, state.measured_pose[i],
                                               state.odometry[i]))
        if transforms:
            self._dynamic.publish(TFMessage(transforms=transforms))

    def close(self) -> None:
        """Withdraw the topics."""
        self._dynamic.unregister()
        self._static.unregister()
