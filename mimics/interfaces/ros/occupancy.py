"""Rasterising a map's exact wall segments into an occupancy grid (for ``/map``).

A cell is occupied when a wall segment passes through it. Cells are
half-open squares ``[x, x + resolution) x [y, y + resolution)`` from the
lower-left corner of the map's bounds, so a segment lying exactly on a grid
line marks the cells above or to the right of it. Each segment is swept
column by column: within a column it spans one interval of y, and the cells
of that interval are exactly the ones it crosses there. No sampling: a
segment shorter than a cell still marks its cell.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mimics.world.errors import MimicsError
from mimics.world.maps import Map

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
    """The cells of ``world``'s bounds that its wall segments pass through.

    >>> from mimics.world.maps import Map
    >>> grid = rasterise(Map([[0.05, 0.05, 0.35, 0.05]], (0, 0, 1, 1)), 0.1)
    >>> grid.cells.shape, int(grid.cells[0, :5].sum())
    ((10, 10), 300)

    Args:
        world: the map (its segments and bounds).
        resolution: the side of a cell in metres.

    Raises:
        MimicsError: when the resolution is not a positive number, or gives
            more than 100 million cells.
    """
    if not (isinstance(resolution, int | float) and math.isfinite(resolution)
            and resolution > 0):
        raise MimicsError(f"map resolution: expected a positive number of metres, "
                          f"got {resolution!r}")
    xmin, ymin, xmax, ymax = world.bounds
    width = max(1, math.ceil((xmax - xmin) / resolution - 1e-9))
    height = max(1, math.ceil((ymax - ymin) / resolution - 1e-9))
    if width * height > 100_000_000:
        raise MimicsError(f"map resolution: {resolution:g} m gives {width} x {height} cells "
                          "(over 100 million); choose a coarser resolution")
    cells = np.full((height, width), FREE, dtype=np.int8)
    units = (np.asarray(world.segments, dtype=np.float64)
             - np.array([xmin, ymin, xmin, ymin])) / resolution
    for x1, y1, x2, y2 in units.tolist():
        rows, columns = _segment_cells(x1, y1, x2, y2)
        inside = (rows >= 0) & (rows < height) & (columns >= 0) & (columns < width)
        cells[rows[inside], columns[inside]] = OCCUPIED
    return Grid(cells, float(resolution), (float(xmin), float(ymin)))


def _segment_cells(x1: float, y1: float, x2: float, y2: float) -> tuple[np.ndarray, np.ndarray]:
    """Rows and columns of the unit cells a segment (in cell units) passes through."""
    if x1 > x2:
        x1, y1, x2, y2 = x2, y2, x1, y1
    first, last = math.floor(x1), math.floor(x2)
    if first == last:  # within one column (vertical segments included)
        low, high = math.floor(min(y1, y2)), math.floor(max(y1, y2))
        rows = np.arange(low, high + 1)
        return rows, np.full(rows.shape, first)
    # x where the segment enters and leaves each column it crosses
    columns = np.arange(first, last + 1)
    edges = np.concatenate(([x1], np.arange(first + 1, last + 1, dtype=np.float64), [x2]))
    slope = (y2 - y1) / (x2 - x1)
    ys = y1 + (edges - x1) * slope
    ys[0], ys[-1] = y1, y2  # the exact end points, not recomputed
    low = np.floor(np.minimum(ys[:-1], ys[1:])).astype(np.int64)
    high = np.floor(np.maximum(ys[:-1], ys[1:])).astype(np.int64)
    counts = high - low + 1
    column_of = np.repeat(columns, counts)
    starts = np.repeat(low - np.cumsum(counts) + counts, counts)
    rows = starts + np.arange(int(counts.sum()))
    return rows, column_of
