"""sensor_msgs/LaserScan: the scans a run recorded (``--record-scans``).

One message per row of scans.parquet on the robot's scan topic of
:class:`~mimics.interfaces.ros.names.RosNames` (``/robot_i/scan``, frame
``robot_i/laser``; ``base_scan``, frame ``base_laser_link``, under the
``stage`` names). ``angle_min``/``angle_max`` are the first and last beam
angles of the robot's type (right to left, as the engine's), ``range_min``
0, ``range_max`` its ranger's range, ``scan_time`` the step. Ranges are the
recorded ones (within half the recording's quantum, 0.5 mm, of the engine's)
as float32; a beam that hit nothing is ``+inf``, as REP 117 asks, so that
viewers draw no point for it, or ``range_max`` under the ``stage`` names (what
``stage_ros`` and the live bridge under those names publish).
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from mimics.interfaces.ros.names import RosNames
from mimics.interfaces.rosexport.conversion import Messages, Stamped, nanoseconds
from mimics.interfaces.rosexport.topics import LASER_SCAN
from mimics.records.scans import ScanRecord, decode


def scan_messages(messages: Messages, scans: ScanRecord, dt: float,
                  names: RosNames) -> Iterator[Stamped]:
    """One LaserScan per recorded scan, in (step, robot) order."""
    table = scans.table.sort_by([("step", "ascending"), ("robot", "ascending")])
    for batch in table.to_batches(max_chunksize=4096):
        robots = batch["robot"].to_numpy()
        times = batch["time"].to_numpy()
        offsets = batch["ranges"].offsets.to_numpy()
        offsets = offsets - offsets[0]
        ranges = decode(batch["ranges"], scans.quantum).astype(np.float32)
        hits = batch["hits"].flatten().to_numpy(zero_copy_only=False).astype(bool)
        no_return = ~hits
        ranges[no_return] = np.inf
        for k in range(batch.num_rows):
            robot = int(robots[k])
            angles = scans.angles(robot)
            max_range = float(scans.max_range(robot))
            values = ranges[offsets[k]:offsets[k + 1]]
            if names.stage:
                values = np.where(no_return[offsets[k]:offsets[k + 1]], np.float32(max_range),
                                  values)
            stamp = nanoseconds(times[k])
            increment = float(angles[1] - angles[0]) if angles.size > 1 else 0.0
            message = messages.make(
                LASER_SCAN, header=messages.header(stamp, names.laser_frame(robot)),
                angle_min=float(angles[0]), angle_max=float(angles[-1]),
                angle_increment=increment, scan_time=float(dt), range_min=0.0,
                range_max=max_range, ranges=values)
            yield Stamped(stamp, names.scan(robot), message)
