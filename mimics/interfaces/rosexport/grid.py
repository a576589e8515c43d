"""nav_msgs/OccupancyGrid: the map's walls, rasterised from the exact segments by
:func:`mimics.world.occupancy.occupied_cells` (re-exported here as ``rasterise``),
row by row from the bottom (ROS's order: cell ``(row, col)`` is
``data[row * width + col]``), 100 where a wall passes, else 0.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from mimics.interfaces.rosexport.conversion import Messages, Stamped, nanoseconds
from mimics.interfaces.rosexport.topics import MAP_FRAME, MAP_TOPIC, OCCUPANCY_GRID
from mimics.world.maps import Map
from mimics.world.occupancy import check_resolution, grid_shape
from mimics.world.occupancy import occupied_cells as rasterise

__all__ = ["check_resolution", "grid_shape", "map_messages", "rasterise"]

OCCUPIED = 100
FREE = 0


def map_messages(messages: Messages, world: Map, resolution: float) -> Iterator[Stamped]:
    """The one OccupancyGrid of the map, at time 0."""
    start = nanoseconds(0.0)
    occupied = rasterise(world, resolution)
    height, width = occupied.shape
    data = np.where(occupied, OCCUPIED, FREE).astype(np.int8).reshape(-1)
    info = messages.make("nav_msgs/msg/MapMetaData", map_load_time=messages.stamp(start),
                         resolution=float(resolution), width=width, height=height,
                         origin=messages.pose(world.bounds[0], world.bounds[1], 0.0))
    yield Stamped(start, MAP_TOPIC, messages.make(OCCUPANCY_GRID,
                                                  header=messages.header(start, MAP_FRAME),
                                                  info=info, data=data))
