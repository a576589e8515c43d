"""Which walls a range finder must look at, cell by cell (built once per map).

A :class:`WallIndex` pairs two grids over the same walls:

- ``near``: for every cell of a coarse grid, the walls that come within
  ``reach`` metres of any point of the cell, less those another wall hides
  from the whole cell (``wall_occlusion.py``). A sensor anywhere in the cell
  finds every hit nearer than ``reach`` among them, so the ranger sweeps
  just those walls once per robot, each over the beams it spans (see
  ``ranger.py``);
- ``grid``: the fine grid that beams walk cell by cell (``spatial_index.py``)
  for hits beyond ``reach``, and that collisions use.

``reach`` is the longest sensor range when that fits the memory budget
(every map of the paper: the 8 m Cave, the 2 m Hospital), shorter otherwise;
then the walk picks up where the sweep's certainty ends.

>>> segments = np.array([[3.0, -1.0, 3.0, 1.0], [9.0, -1.0, 9.0, 1.0]])
>>> index = build_wall_index(segments, (-10, -10, 10, 10), reach=4.0)
>>> cell = near_cell_of(index.near, 0.0, 0.0)
>>> index.near.cell_items[index.near.cell_start[cell]:index.near.cell_start[cell + 1]].tolist()
[0]
"""

from __future__ import annotations

import hashlib
import math
import threading
from collections import OrderedDict
from typing import NamedTuple

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.compiling.kernel_options import INNER
from mimics.engine.ranging.wall_occlusion import MARGIN, cull_hidden
from mimics.engine.spatial_index import (
    Bounds,
    SegmentGrid,
    as_segments,
    build_segment_grid,
    cell_span,
    clip_to_slab,
    coerce_grid,
    covering_box,
    grid_frame,
)

MAX_NEAR_ITEMS = 8_000_000  # budget for the near lists (64 MB of int64)
CELLS_PER_REACH = 8  # near cells are about reach / 8: candidates exceed the disc by ~30%


class WallIndex(NamedTuple):
    """Walls indexed for sensing (read it, never mutate it).

    Attributes:
        grid: the fine walking grid of all walls.
        near: coarse grid whose cell lists hold the walls within ``reach`` of
            the cell that no other wall hides from all of it (``near.segments``
            is ``grid.segments``).
        reach: hits nearer than this are found by sweeping ``near`` alone (m).
    """

    grid: SegmentGrid
    near: SegmentGrid
    reach: float


@njit(**INNER)
def _point_box_distance(px: float, py: float, x0: float, y0: float, x1: float,
                        y1: float) -> float:
    dx = larger(x0 - px, 0.0, px - x1)
    dy = larger(y0 - py, 0.0, py - y1)
    return math.hypot(dx, dy)


@njit(**INNER)
def point_segment_distance(px: float, py: float, x1: float, y1: float, x2: float,
                           y2: float) -> float:
    """Euclidean distance from a point to a closed segment."""
    ex, ey = x2 - x1, y2 - y1
    length2 = ex * ex + ey * ey
    s = 0.0
    if length2 > 0.0:
        s = smaller(larger(((px - x1) * ex + (py - y1) * ey) / length2, 0.0), 1.0)
    gx, gy = px - x1 - s * ex, py - y1 - s * ey
    return math.sqrt(gx * gx + gy * gy)  # hypot's overflow care costs 3x here


@njit(**INNER)
def _segment_crosses_box(x1: float, y1: float, x2: float, y2: float, x0: float, y0: float,
                         xb: float, yb: float) -> bool:
    """Whether a segment has a point in the closed box ``[x0, xb] x [y0, yb]``."""
    s0, s1 = clip_to_slab(x1, x2 - x1, x0, xb, 0.0, 1.0)
    s0, s1 = clip_to_slab(y1, y2 - y1, y0, yb, s0, s1)
    return s0 <= s1


@njit(cache=True)
def segment_box_distance(x1: float, y1: float, x2: float, y2: float, x0: float, y0: float,
                         xb: float, yb: float) -> float:
    """Distance between a segment and the closed box ``[x0, xb] x [y0, yb]``.

    Disjoint convex polygons are nearest between a vertex of one and the other.
    """
    if _segment_crosses_box(x1, y1, x2, y2, x0, y0, xb, yb):
        return 0.0
    d = smaller(_point_box_distance(x1, y1, x0, y0, xb, yb),
            _point_box_distance(x2, y2, x0, y0, xb, yb))
    for cx, cy in ((x0, y0), (xb, y0), (x0, yb), (xb, yb)):
        d = smaller(d, point_segment_distance(cx, cy, x1, y1, x2, y2))
    return d


@njit(cache=True)
def _near_lists(segments: np.ndarray, origin: np.ndarray, shape: np.ndarray, cell: float,
                reach: float) -> tuple[np.ndarray, np.ndarray]:
    """CSR lists of the segments within ``reach`` of each cell (count, then fill)."""
    nx, ny = shape[0], shape[1]
    start = np.zeros(nx * ny + 1, dtype=np.int64)
    items = np.empty(0, dtype=np.int64)
    cursor = np.empty(0, dtype=np.int64)
    for fill in (False, True):
        if fill:
            for c in range(nx * ny):
                start[c + 1] += start[c]
            items = np.empty(start[nx * ny], dtype=np.int64)
            cursor = start[: nx * ny].copy()
        for s in range(segments.shape[0]):
            x1, y1, x2, y2 = segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3]
            ix0, ix1 = cell_span(smaller(x1, x2) - reach, larger(x1, x2) + reach, origin[0],
                                 cell, nx)
            iy0, iy1 = cell_span(smaller(y1, y2) - reach, larger(y1, y2) + reach, origin[1],
                                 cell, ny)
            for iy in range(iy0, iy1 + 1):
                y0 = origin[1] + iy * cell
                for ix in range(ix0, ix1 + 1):
                    x0 = origin[0] + ix * cell
                    if segment_box_distance(x1, y1, x2, y2, x0, y0, x0 + cell,
                                            y0 + cell) > reach:
                        continue
                    c = iy * nx + ix
                    if fill:
                        items[cursor[c]] = s
                        cursor[c] += 1
                    else:
                        start[c + 1] += 1
    return start, items


def _near_items_estimate(segments: np.ndarray, cell: float, reach: float) -> float:
    """About how many entries the near lists of ``cell`` and ``reach`` hold."""
    lengths = np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])
    side = 2.0 * reach + cell
    return float(np.sum((lengths + side) * side)) / cell**2


@njit(cache=True)
def near_cell_of(near: SegmentGrid, x: float, y: float) -> int:
    """The cell of ``near`` (a ``WallIndex.near``) holding ``(x, y)``, or -1 outside it."""
    nx, ny = near.shape[0], near.shape[1]
    fx = (x - near.origin[0]) / near.cell
    fy = (y - near.origin[1]) / near.cell
    if not (0.0 <= fx < nx and 0.0 <= fy < ny):
        return -1
    return int(fy) * nx + int(fx)


def build_wall_index(segments: np.ndarray, bounds: Bounds | None, reach: float,
                     cell: float | None = None, near_cell: float | None = None,
                     grid: SegmentGrid | None = None) -> WallIndex:
    """Index walls for sensors of range up to ``reach`` (m).

    Args:
        segments: ``(m, 4)`` walls ``x1, y1, x2, y2``.
        bounds: the box to cover (the map's bounds), or None.
        reach: the longest sensor range to serve by sweeping alone; it is
            shortened when the near lists would exceed ``MAX_NEAR_ITEMS``.
        cell: cell of the walking grid (default: ``choose_cell_size``).
        near_cell: cell of the near grid (default: about ``reach / 8``, never
            finer than the walking grid's).
        grid: the walking grid of these walls, when built already
            (``build_segment_grid(segments, bounds, cell=cell)``).

    Returns:
        The index.

    Raises:
        ValueError: non-finite walls or bounds, a negative or NaN reach, or
            a non-positive cell.
    """
    segs = as_segments(segments)
    if grid is None:
        grid = build_segment_grid(segs, bounds, cell=cell)
    if not reach >= 0.0:
        raise ValueError(f"reach must be a number >= 0, got {reach!r}")
    xmin, ymin, xmax, ymax = covering_box(segs, bounds)
    longest = max(xmax - xmin, ymax - ymin, 1e-9)
    reach = float(min(reach, 2.0 * longest))  # beyond the map's diagonal nothing changes
    if near_cell is None:
        size = min(max(grid.cell, reach / CELLS_PER_REACH), longest)
        while len(segs) and _near_items_estimate(segs, size, reach) > MAX_NEAR_ITEMS:
            if size < reach:
                size *= 2.0
            else:
                reach /= 2.0
    else:
        size = float(near_cell)
        if not (math.isfinite(size) and size > 0):
            raise ValueError(f"near_cell must be a positive number, got {near_cell!r}")
    origin, shape, size = grid_frame(xmin, ymin, xmax, ymax, size)
    # the near lists are conservative: pad the reach for rounding in the distance tests
    start, items = _near_lists(segs, origin, shape, size, reach * (1 + 1e-9) + 1e-9)
    start, items = cull_hidden(segs, origin, shape, size, start, items, MARGIN)
    near = SegmentGrid(segs, grid.owner, origin, size, shape, start, items)
    return WallIndex(grid, near, reach)


# the last maps' indexes in this process: a battery worker, a learning environment's
# resets or a notebook run map after map of the same few (the Hospital's takes 0.1 s)
_SHARED_INDEXES = 4
_SharedKey = tuple[bytes, tuple[int, ...], tuple[float, ...] | None, float]
_shared: OrderedDict[_SharedKey, WallIndex] = OrderedDict()
_shared_lock = threading.Lock()


def shared_wall_index(segments: np.ndarray, bounds: Bounds | None, reach: float,
                      grid: SegmentGrid) -> WallIndex:
    """``build_wall_index(segments, bounds, reach, grid=grid)``, built once per process
    for the last few maps asked for: the same walls, bounds and reach give the same
    index object (read by the kernels only, never written). ``grid`` must be the
    walking grid of these walls with the default cell."""
    walls = as_segments(segments)
    box = None if bounds is None else tuple(float(b) for b in bounds)
    key = (hashlib.blake2b(walls.tobytes(), digest_size=16).digest(), walls.shape, box,
           float(reach))
    with _shared_lock:
        found = _shared.get(key)
        if found is not None:
            _shared.move_to_end(key)
            return found
    index = build_wall_index(walls, bounds, reach, grid=grid)
    with _shared_lock:
        _shared[key] = index
        while len(_shared) > _SHARED_INDEXES:
            _shared.popitem(last=False)
    return index


def coerce_wall_index(index: WallIndex) -> WallIndex:
    """``index`` with canonical field types (one compiled kernel for all callers)."""
    return WallIndex(coerce_grid(index.grid), coerce_grid(index.near), float(index.reach))
