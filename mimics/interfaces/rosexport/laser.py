"""sensor_msgs/LaserScan: the scans a run recorded (``--record-scans``).

One message per row of scans.parquet on ``/robot_i/scan``, frame
``robot_i/laser``. ``angle_min``/``angle_max`` are the first and last beam
angles of the robot's type (right to left, as the engine's), ``range_min``
0, ``range_max`` its ranger's range, ``scan_time`` the step. Ranges are the
recorded ones (within half the recording's quantum, 0.5 mm, of the engine's)
as float32; a beam that hit nothing is ``+inf``, as REP 117 asks, so that
viewers draw no point for it.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from mimics.interfaces.rosexport.conversion import Messages, Stamped, nanoseconds
from mimics.interfaces.rosexport.topics import LASER_SCAN, laser_frame, scan_topic
from mimics.records.scans import ScanRecord, decode


def scan_messages(messages: Messages, scans: ScanRecord, dt: float) -> Iterator[Stamped]:
    """One LaserScan per recorded scan, in (step, robot) order."""
    table = scans.table.sort_by([("step", "ascending"), ("robot", "ascending")])
    for batch in table.to_batches(max_chunksize=4096):
        robots = batch["robot"].to_numpy()
        times = batch["time"].to_numpy()
        offsets = batch["ranges"].offsets.to_numpy()
        offsets = offsets - offsets[0]
        ranges = decode(batch["ranges"], scans.quantum).astype(np.float32)
        hits = batch["hits"].flatten().to_numpy(zero_copy_only=False).astype(bool)
        ranges[~hits] = np.inf
        for k in range(batch.num_rows):
            robot = int(robots[k])
            angles = scans.angles(robot)
            stamp = nanoseconds(times[k])
            increment = float(angles[1] - angles[0]) if angles.size > 1 else 0.0
            message = messages.make(
                LASER_SCAN, header=messages.header(stamp, laser_frame(robot)),
                angle_min=float(angles[0]), angle_max=float(angles[-1]),
                angle_increment=increment, scan_time=float(dt), range_min=0.0,
                range_max=float(scans.max_range(robot)),
                ranges=ranges[offsets[k]:offsets[k + 1]])
            yield Stamped(stamp, scan_topic(robot), message)
