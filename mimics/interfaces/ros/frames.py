"""tf2 frames (REP 105), names from :mod:`~mimics.interfaces.ros.names`.

Every step on ``/tf``, per robot the step publishes: ``map -> odom`` (the
correction that puts the body at the measured pose in ``map``; only with
``map_odom``, the bridge's ``--publish-map-odom``: stage_ros publishes none,
leaving it to a localiser such as ``amcl``) and ``odom -> body`` (the
odometer's pose in its ``odom`` frame). Once on the latched
``/tf_static``: ``base_footprint -> base_link`` (``stage`` names) and
``base_link -> laser`` (``base_laser_link``), both the identity: the ranger
sits at the robot's centre, facing forward.

``/tf`` is latched (one message per step holds every robot's frames), so a
listener that connects late still gets the current step's. Published as
plain ``tf2_msgs/TFMessage`` (what ``tf2_ros``' broadcasters send), so no
compiled part of tf2 is loaded.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import rospy
from tf2_msgs.msg import TFMessage

from mimics.interfaces.ros.conversion import fixed_transform, odometry_transforms
from mimics.interfaces.ros.names import RosNames
from mimics.interfaces.ros.readings import fixed_frames

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation
    from mimics.interfaces.ros.odometry_frame import OdometerFrames


class FramePublisher:
    """Broadcasts every robot's frames."""

    def __init__(self, beam_count: np.ndarray, names: RosNames,
                 odometer: OdometerFrames, map_odom: bool = True) -> None:
        self.names = names
        self.map_odom = map_odom  # map -> odom too (else odom -> body only)
        self.odometer = odometer  # the odometry publisher's: updated before this publishes
        # latched: a listener that connects late (the run waits for the nodes' odometry
        # and scan subscriptions, not for /tf) still gets the current step's frames
        self._dynamic = rospy.Publisher("/tf", TFMessage, queue_size=100, latch=True)
        self._static = rospy.Publisher("/tf_static", TFMessage, queue_size=1, latch=True)
        fixed = [fixed_transform(parent, child)
                 for parent, child in fixed_frames(beam_count, names)]
        self._static.publish(TFMessage(transforms=fixed))

    def publish(self, sim: Simulation, ids: np.ndarray) -> None:
        """The frames of robots ``ids`` at the current step, in one message."""
        state, names = sim.state, self.names
        transforms = []
        for i in ids.tolist():
            transforms.extend(odometry_transforms(state.time, names.odom_frame(i),
                                                  names.body_frame(i), state.measured_pose[i],
                                                  self.odometer.pose[i], self.map_odom))
        if transforms:
            self._dynamic.publish(TFMessage(transforms=transforms))

    def close(self) -> None:
        """Withdraw the topics."""
        self._dynamic.unregister()
        self._static.unregister()
