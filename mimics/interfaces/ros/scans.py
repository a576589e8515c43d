"""Each active robot's ranger reading (``scan``, or ``base_scan`` under the stage names),
with its real angles and range.

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

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation


class ScanPublisher:
    """Publishes ``sensor_msgs/LaserScan`` for every robot that has a ranger."""

    def __init__(self, beam_count: np.ndarray, names: RosNames) -> None:
        self.beam_count = beam_count
        self.names = names
        self.publishers = {i: rospy.Publisher(names.scan(i), LaserScan,
                                              queue_size=10, tcp_nodelay=True,
                                              latch=True)
                           for i in np.flatnonzero(beam_count > 0).tolist()}

    def publish(self, sim: Simulation, ids: np.ndarray) -> None:
        """The scans of robots ``ids`` at the current step."""
        state, types = sim.state, sim.types
        for i in ids.tolist():
            publisher = self.publishers.get(i)
            if publisher is None:
                continue
            beams = int(self.beam_count[i])
            publisher.publish(scan_message(
                self.names.laser_frame(i), state.time, state.scan[i, :beams],
                state.scan_hit[i, :beams] != -2, types.beam_offsets[i, :beams],
                float(types.max_range[i]), sim.scenario.settings.dt,
                no_return_at_max=self.names.stage))  # stage_ros: range_max, not inf

    def close(self) -> None:
        """Withdraw the topics."""
        for publisher in self.publishers.values():
            publisher.unregister()
