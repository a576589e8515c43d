"""The map as the live bridge's occupancy grid (``/map``): the cells
:mod:`mimics.world.occupancy` finds a wall in, with their size and origin.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimics.world.maps import Map
from mimics.world.occupancy import occupied_cells

OCCUPIED = 100  # nav_msgs/OccupancyGrid: probability of occupancy in percent
FREE = 0


@dataclass(frozen=True)
class Grid:
    """An occupancy grid: ``cells[row, column]``, row 0 at the bottom (``origin`` y)."""

    cells: np.ndarray  # (height, width) int8: OCCUPIED or FREE
    resolution: float  # metres per cell
    origin: tuple[float, float]  # world coordinates of the lower-left corner of cell (0, 0)

    @property
    def width(self) -> int:
        """Cells along x."""
        return int(self.cells.shape[1])

    @property
    def height(self) -> int:
        """Cells along y."""
        return int(self.cells.shape[0])


def rasterise(world: Map, resolution: float) -> Grid:
    """The cells of ``world``'s bounds that its wall segments pass through
    (:func:`mimics.world.occupancy.occupied_cells`), as ROS's occupancy values.

    >>> from mimics.world.maps import Map
    >>> grid = rasterise(Map([[0.05, 0.05, 0.35, 0.05]], (0, 0, 1, 1)), 0.1)
    >>> grid.cells.shape, int(grid.cells[0, :5].sum())
    ((10, 10), 400)

    Raises:
        MimicsError: when the resolution is not a positive number, or gives
            more than 100 million cells.
    """
    occupied = occupied_cells(world, resolution, name="map resolution")
    cells = np.where(occupied, OCCUPIED, FREE).astype(np.int8)
    return Grid(cells, float(resolution), (float(world.bounds[0]), float(world.bounds[1])))
