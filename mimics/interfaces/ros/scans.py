"""Each robot's ranger reading (``scan``, or ``base_scan`` under the stage names), with
its real angles and range; under the stage names as stage_ros fills it: ``range_max``
where a beam hit nothing, and intensities (1.0 where a beam hit something, else 0.0).

A mimics robot has at most one ranger, so the topic is ``scan`` or
``base_scan`` (the names object numbers them when a robot has several).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
import rospy
from sensor_msgs.msg import LaserScan

from mimics.interfaces.ros.conversion import scan_message
from mimics.interfaces.ros.names import RosNames
from mimics.interfaces.ros.readings import ScanReadings

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation


class ScanPublisher:
    """Publishes ``sensor_msgs/LaserScan`` for every robot that has a ranger."""

    def __init__(self, sim: Simulation, names: RosNames) -> None:
        self.readings = ScanReadings(sim)  # what each scan carries (shared with ROS 2)
        self.names = names
        self.publishers = {i: rospy.Publisher(names.scan(i), LaserScan,
                                              queue_size=10, tcp_nodelay=True,
                                              latch=True)
                           for i in np.flatnonzero(sim.types.beam_count > 0).tolist()}

    def publish(self, sim: Simulation, ids: np.ndarray) -> None:
        """The scans of robots ``ids`` at the current step."""
        types, stage = sim.types, self.names.stage
        for i in ids.tolist():
            publisher = self.publishers.get(i)
            if publisher is None:
                continue
            ranges, hit = self.readings.scan(sim, i)
            # stage_ros: range_max where a beam hit nothing (not inf), and intensities
            publisher.publish(scan_message(
                self.names.laser_frame(i), sim.state.time, ranges, hit,
                types.beam_offsets[i, :len(ranges)], float(types.max_range[i]),
                sim.scenario.settings.dt, no_return_at_max=stage, intensities=stage))

    def close(self) -> None:
        """Withdraw the topics."""
        for publisher in self.publishers.values():
            publisher.unregister()
