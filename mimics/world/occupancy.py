"""A map's exact wall segments rasterised into occupancy cells (for ROS's ``/map``).

The grid covers the map's bounds from their lower-left corner in square cells
of ``resolution`` metres, row 0 at the bottom. A cell is occupied when a wall
segment passes through it: each segment is walked column by column, and in
each column every cell between the segment's lowest and highest point there
is marked, so no cell a wall crosses is missed however thin or steep the wall
(no sampling). Cells are half open (``[x0, x0 + r)``), except that a wall on
the bounds' upper or right edge (a box's walls) marks the last row or column
rather than falling outside.

>>> grid = occupied_cells(Map(segments=[(0.25, 0.25, 1.75, 0.25)], bounds=(0, 0, 2, 1)), 0.5)
>>> grid.astype(int).tolist()
[[1, 1, 1, 1], [0, 0, 0, 0]]
"""

from __future__ import annotations

import math

import numpy as np

from mimics.world.errors import MimicsError
from mimics.world.maps import Bounds, Map

MAX_CELLS = 100_000_000


def grid_shape(bounds: Bounds, resolution: float) -> tuple[int, int]:
    """``(height, width)`` in cells of a grid covering ``bounds``."""
    xmin, ymin, xmax, ymax = bounds
    return (max(1, math.ceil((ymax - ymin) / resolution - 1e-9)),
            max(1, math.ceil((xmax - xmin) / resolution - 1e-9)))


def check_resolution(resolution: object, bounds: Bounds | None = None,
                     name: str = "resolution") -> None:
    """Raise a one-line :class:`MimicsError` unless ``resolution`` is a positive number
    (and, given ``bounds``, gives at most :data:`MAX_CELLS` cells); ``name`` starts it."""
    if (isinstance(resolution, bool) or not isinstance(resolution, int | float)
            or not (resolution > 0 and math.isfinite(resolution))):
        raise MimicsError(f"{name}: expected a positive number of metres, got {resolution!r}")
    if bounds is not None:
        height, width = grid_shape(bounds, resolution)
        if height * width > MAX_CELLS:
            raise MimicsError(f"{name}: {resolution:g} m gives {width} x {height} cells (over "
                              f"{MAX_CELLS:,}); choose a coarser resolution")


def occupied_cells(world: Map, resolution: float, name: str = "resolution") -> np.ndarray:
    """``(height, width)`` booleans: the cells a wall passes through, row 0 at the bottom.

    Raises:
        MimicsError: when ``resolution`` is not a positive number, or gives too many cells.
    """
    check_resolution(resolution, world.bounds, name)
    height, width = grid_shape(world.bounds, resolution)
    occupied = np.zeros((height, width), dtype=bool)
    xmin, ymin = world.bounds[0], world.bounds[1]
    for x1, y1, x2, y2 in world.segments:
        u1, v1 = (x1 - xmin) / resolution, (y1 - ymin) / resolution
        u2, v2 = (x2 - xmin) / resolution, (y2 - ymin) / resolution
        if u1 > u2:
            u1, v1, u2, v2 = u2, v2, u1, v1
        columns = np.arange(_cell(u1, width), _cell(u2, width) + 1)
        if u2 > u1:  # the segment's ends within each column it crosses
            left = np.maximum(u1, columns)
            right = np.minimum(u2, columns + 1.0)
            slope = (v2 - v1) / (u2 - u1)
            low_v, high_v = v1 + slope * (left - u1), v1 + slope * (right - u1)
        else:  # vertical: one column
            low_v, high_v = np.array([v1]), np.array([v2])
        low = _cells(np.minimum(low_v, high_v), height)
        high = _cells(np.maximum(low_v, high_v), height)
        counts = high - low + 1
        cols = np.repeat(columns, counts)
        rows = np.repeat(low, counts) + (np.arange(counts.sum()) - np.repeat(np.cumsum(counts)
                                                                              - counts, counts))
        inside = (cols >= 0) & (cols < width) & (rows >= 0) & (rows < height)
        occupied[rows[inside], cols[inside]] = True
    return occupied


def _cells(coordinates: np.ndarray, cells: int) -> np.ndarray:
    """The cell index of each coordinate (in cells); the far edge belongs to the last cell."""
    index = np.floor(coordinates).astype(np.int64)
    return np.where(coordinates == cells, cells - 1, index)


def _cell(coordinate: float, cells: int) -> int:
    return int(_cells(np.array([coordinate]), cells)[0])
