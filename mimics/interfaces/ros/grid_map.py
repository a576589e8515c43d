"""``/map``: the walls as a latched ``nav_msgs/OccupancyGrid``, published once."""

from __future__ import annotations

import rospy
from nav_msgs.msg import OccupancyGrid

from mimics.interfaces.ros.conversion import grid_message
from mimics.interfaces.ros.occupancy import rasterise
from mimics.world.maps import Map


class MapPublisher:
    """Rasterises the map's segments at ``resolution`` and latches the grid on ``/map``."""

    def __init__(self, world: Map, resolution: float) -> None:
        self.grid = rasterise(world, resolution)
        self._publisher = rospy.Publisher("/map", OccupancyGrid, queue_size=1, latch=True)
        self._publisher.publish(grid_message(self.grid, 0.0))

    def close(self) -> None:
        """Withdraw the topic."""
        self._publisher.unregister()
