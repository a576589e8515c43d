"""Uniform grids over line segments (the walls) in CSR layout.

A :class:`SegmentGrid` lists, for every square cell, the segments whose
geometry crosses that cell (an exact segment-versus-box test, not the
segment's bounding box, so a long diagonal wall fills only the cells along
it). Cell ``iy * nx + ix`` owns ``cell_items[cell_start[c]:cell_start[c + 1]]``.

Each cell is tested slightly enlarged (by :func:`grid_pad`, about 1e-9 of the
coordinates' magnitude), so that floating-point rounding in the kernels that
walk the grid (``ray_kernel.py``, ``collision.py``) can never miss a segment that
passes exactly through a cell's corner or along its side.

Numba's on-disk cache does not notice edits to the helpers here when it
loads the kernels of ``ray_kernel.py`` and ``collision.py`` that call them: after
changing this file, delete ``mimics/engine/__pycache__``.

>>> import numpy as np
>>> diagonal = np.array([[0.2, 0.5, 9.8, 9.6]])
>>> grid = build_segment_grid(diagonal, (0.0, 0.0, 10.0, 10.0), cell=1.0)
>>> grid.shape.tolist(), len(grid.cell_items)  # 19 of the 100 cells under its box
([10, 10], 19)
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.compiling.kernel_options import INNER

Bounds = tuple[float, float, float, float]

PAD_RELATIVE = 1e-9  # cell enlargement, relative to the largest coordinate (>= 1 m)
MARGIN_RELATIVE = 1e-7  # the grid's box exceeds what it must cover by this much
MAX_CELLS = 1 << 25  # refuse grids with more cells than this (256 MiB of offsets)


class SegmentGrid(NamedTuple):
    """Segments bucketed into a uniform grid (read it, never mutate it).

    Attributes:
        segments: ``(m, 4)`` float64 ``x1, y1, x2, y2``.
        owner: ``(m,)`` int64; -1 for a wall, else the index of the robot the
            segment is an edge of.
        origin: ``(2,)`` float64 lower-left corner of the grid.
        cell: side of a cell (m).
        shape: ``(2,)`` int64 ``nx, ny``.
        cell_start: ``(nx * ny + 1,)`` int64 CSR offsets into ``cell_items``.
        cell_items: ``(k,)`` int64 segment indices, cell after cell.
    """

    segments: np.ndarray
    owner: np.ndarray
    origin: np.ndarray
    cell: float
    shape: np.ndarray
    cell_start: np.ndarray
    cell_items: np.ndarray


# -- small compiled helpers shared with ray_kernel.py and collision.py -----------


@njit(cache=True)
def grid_pad(origin: np.ndarray, shape: np.ndarray, cell: float) -> float:
    """How much every cell is enlarged when segments are listed in it (m)."""
    x1 = origin[0] + shape[0] * cell
    y1 = origin[1] + shape[1] * cell
    span = larger(1.0, abs(origin[0]), abs(origin[1]), abs(x1), abs(y1))
    return PAD_RELATIVE * span


@njit(**INNER, inline="always")
def clip_to_slab(start: float, delta: float, lo: float, hi: float, s0: float,
                 s1: float) -> tuple[float, float]:
    """Narrow ``[s0, s1]``, parameters of ``start + s * delta``, to ``lo <= . <= hi``.

    One axis of Liang-Barsky clipping; the result is empty (``s0 > s1``) when
    no parameter qualifies.
    """
    if delta == 0.0:
        return (s0, s1) if lo <= start <= hi else (1.0, 0.0)
    a, b = (lo - start) / delta, (hi - start) / delta
    return larger(s0, smaller(a, b)), smaller(s1, larger(a, b))


@njit(**INNER)
def cell_span(lo: float, hi: float, start: float, cell: float, n: int) -> tuple[int, int]:
    """Indices ``first, last`` of the cells of one axis overlapping ``[lo, hi]``.

    Returns ``first > last`` when the interval misses the axis' ``n`` cells.
    """
    if hi < start or lo > start + n * cell or lo > hi:
        return 0, -1
    # clamp as floats first: far-away coordinates must not overflow int64
    a = smaller(larger(math.floor((lo - start) / cell), 0.0), n - 1.0)
    b = smaller(larger(math.floor((hi - start) / cell), 0.0), n - 1.0)
    return int(a), int(b)


@njit(**INNER)
def _x_extent_in_slab(x1: float, y1: float, x2: float, y2: float,
                      ylo: float, yhi: float) -> tuple[bool, float, float]:
    """x-range of the part of a segment with ``ylo <= y <= yhi`` (``ok`` False if none)."""
    if y1 == y2:
        if y1 < ylo or y1 > yhi:
            return False, 0.0, 0.0
        return True, smaller(x1, x2), larger(x1, x2)
    s0 = (ylo - y1) / (y2 - y1)
    s1 = (yhi - y1) / (y2 - y1)
    if s0 > s1:
        s0, s1 = s1, s0
    s0 = larger(s0, 0.0)
    s1 = smaller(s1, 1.0)
    if s0 > s1:
        return False, 0.0, 0.0
    xa = x1 + s0 * (x2 - x1)
    xb = x1 + s1 * (x2 - x1)
    return True, smaller(xa, xb), larger(xa, xb)


@njit(**INNER)
def _index_segment(seg: np.ndarray, origin: np.ndarray, shape: np.ndarray, cell: float,
                   pad: float, s: int, counts: np.ndarray, items: np.ndarray,
                   cursor: np.ndarray, fill: bool) -> None:
    """Count (``fill`` False) or list (``fill`` True) segment ``s`` in the cells it crosses.

    Row by row: the part of the segment inside the (padded) row gives an
    x-range, and exactly the cells of that row overlapping it are marked.
    """
    x1, y1, x2, y2 = seg[0], seg[1], seg[2], seg[3]
    nx, ny = shape[0], shape[1]
    iy0, iy1 = cell_span(smaller(y1, y2) - pad, larger(y1, y2) + pad, origin[1], cell, ny)
    for iy in range(iy0, iy1 + 1):
        ylo = origin[1] + iy * cell - pad
        yhi = origin[1] + (iy + 1) * cell + pad
        ok, xa, xb = _x_extent_in_slab(x1, y1, x2, y2, ylo, yhi)
        if not ok:
            continue
        ix0, ix1 = cell_span(xa - pad, xb + pad, origin[0], cell, nx)
        for ix in range(ix0, ix1 + 1):
            c = iy * nx + ix
            if fill:
                items[cursor[c]] = s
                cursor[c] += 1
            else:
                counts[c + 1] += 1


@njit(cache=True)
def _build_csr(segments: np.ndarray, origin: np.ndarray, shape: np.ndarray,
               cell: float) -> tuple[np.ndarray, np.ndarray]:
    """CSR offsets and items of ``segments`` (two passes: count, then fill)."""
    ncell = shape[0] * shape[1]
    pad = grid_pad(origin, shape, cell)
    start = np.zeros(ncell + 1, dtype=np.int64)
    none = np.empty(0, dtype=np.int64)
    # np.bool_: literal True/False would compile _index_segment twice
    for s in range(segments.shape[0]):
        _index_segment(segments[s], origin, shape, cell, pad, s, start, none, none, np.bool_(False))
    for c in range(ncell):
        start[c + 1] += start[c]
    items = np.empty(start[ncell], dtype=np.int64)
    cursor = start[:ncell].copy()
    for s in range(segments.shape[0]):
        _index_segment(segments[s], origin, shape, cell, pad, s, start, items, cursor,
                       np.bool_(True))
    return start, items


@njit(cache=True)
def grid_frame(xmin: float, ymin: float, xmax: float, ymax: float,
           cell: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Origin, ``nx, ny`` and cell side of a grid covering the box with a thin margin.

    The margin keeps segments on the box's sides off the grid's own sides; the
    cell is stretched by about the margin rather than adding a row of cells.
    """
    margin = MARGIN_RELATIVE * larger(1.0, abs(xmin), abs(ymin), abs(xmax), abs(ymax))
    origin = np.array([xmin - margin, ymin - margin])
    shape = np.empty(2, dtype=np.int64)
    shape[0] = larger(1, math.ceil((xmax - xmin) / cell - 1e-9))
    shape[1] = larger(1, math.ceil((ymax - ymin) / cell - 1e-9))
    cell = larger(cell, (xmax - xmin + 2 * margin) / shape[0],
                  (ymax - ymin + 2 * margin) / shape[1])
    return origin, shape, cell


# -- walls ---------------------------------------------------------------------


def coerce_array(values: object, dtype: type, ndim: int, name: str) -> np.ndarray:
    """C-contiguous writeable array of ``dtype`` (one compiled kernel per argument type).

    Raises:
        ValueError: when the array does not have ``ndim`` dimensions.
    """
    arr = np.asarray(values, dtype=dtype)
    if arr.ndim != ndim:
        raise ValueError(f"{name} must have {ndim} dimension(s), got shape {arr.shape}")
    if not arr.flags.c_contiguous or not arr.flags.writeable:
        arr = np.array(arr, dtype=dtype, order="C", copy=True)
    return arr


def as_segments(segments: object, name: str = "segments") -> np.ndarray:
    segs = coerce_array(np.asarray(segments, dtype=np.float64).reshape(-1, 4), np.float64, 2, name)
    if not np.all(np.isfinite(segs)):
        raise ValueError(f"{name} must be finite")
    return segs


def covering_box(segments: np.ndarray, bounds: Bounds | None) -> Bounds:
    """Box covering ``bounds`` and every segment (a unit box when both are empty)."""
    boxes = []
    if bounds is not None:
        b = tuple(float(v) for v in bounds)
        if len(b) != 4 or not all(math.isfinite(v) for v in b) or b[0] > b[2] or b[1] > b[3]:
            raise ValueError(f"bounds must be finite (xmin, ymin, xmax, ymax), got {bounds!r}")
        boxes.append(b)
    if len(segments):
        xs, ys = segments[:, 0::2], segments[:, 1::2]
        boxes.append((float(xs.min()), float(ys.min()), float(xs.max()), float(ys.max())))
    if not boxes:
        return (0.0, 0.0, 1.0, 1.0)
    arr = np.array(boxes)
    return (float(arr[:, 0].min()), float(arr[:, 1].min()),
            float(arr[:, 2].max()), float(arr[:, 3].max()))


def choose_cell_size(segments: np.ndarray, bounds: Bounds | None) -> float:
    """A cell side that keeps both the cells walked per beam and the segments per cell low.

    The rule: twice the median segment length (a typical segment then spans
    one or two cells, and a cell along a chain of short segments holds about
    three), but never so small that the grid has more than about
    ``4 * m + 1024`` cells (memory and build time stay O(m)), and never larger
    than the covered box (an empty map is a single cell).

    Args:
        segments: ``(m, 4)`` segments.
        bounds: ``(xmin, ymin, xmax, ymax)`` the grid must cover, or None.

    Returns:
        The cell side (m), positive.

    >>> choose_cell_size(np.array([[0.0, 0.0, 1.0, 0.0]] * 10), (0, 0, 10, 10))
    2.0
    """
    segs = as_segments(segments)
    xmin, ymin, xmax, ymax = covering_box(segs, bounds)
    w, h = xmax - xmin, ymax - ymin
    longest = max(w, h, 1e-9)
    if len(segs) == 0:
        return float(longest)
    lengths = np.hypot(segs[:, 2] - segs[:, 0], segs[:, 3] - segs[:, 1])
    # np.median's value (the two middle lengths' mean), without the numpy.ma it imports
    low, high = (len(lengths) - 1) // 2, len(lengths) // 2
    middle = np.partition(lengths, (low, high))
    cell = 2.0 * float((middle[low] + middle[high]) / 2)
    cell = max(cell, math.sqrt(w * h / (4 * len(segs) + 1024)), longest / 4096)
    return float(min(cell, longest))


def build_segment_grid(segments: np.ndarray, bounds: Bounds | None, cell: float | None = None,
                       owner: np.ndarray | None = None) -> SegmentGrid:
    """Index segments (the map's walls, usually) in a uniform grid.

    The grid covers ``bounds`` grown to include every segment. Building costs
    O(m + cells crossed + nx * ny); do it once per map, not per step.

    Args:
        segments: ``(m, 4)`` ``x1, y1, x2, y2`` (copied).
        bounds: ``(xmin, ymin, xmax, ymax)`` to cover, or None for the
            segments' own box.
        cell: cell side (m); default :func:`choose_cell_size`. The grid's
            cell may be larger by a relative 1e-7 (see ``grid_frame``).
        owner: ``(m,)`` owner of each segment; default -1 (walls).

    Returns:
        The grid.

    Raises:
        ValueError: non-finite segments or bounds, a bad ``owner`` shape, a
            non-positive cell, or a grid of more than ``MAX_CELLS`` cells.

    >>> grid = build_segment_grid(np.array([[0.5, 0.5, 2.5, 0.5]]), (0, 0, 3, 3), cell=1.0)
    >>> [int(c) for c in range(9) if grid.cell_start[c + 1] > grid.cell_start[c]]
    [0, 1, 2]
    """
    segs = as_segments(segments)
    m = len(segs)
    if owner is None:
        own = np.full(m, -1, dtype=np.int64)
    else:
        own = coerce_array(owner, np.int64, 1, "owner")
        if len(own) != m:
            raise ValueError(f"owner has {len(own)} entries for {m} segments")
    size = choose_cell_size(segs, bounds) if cell is None else float(cell)
    if not (math.isfinite(size) and size > 0):
        raise ValueError(f"cell must be a positive number, got {cell!r}")
    xmin, ymin, xmax, ymax = covering_box(segs, bounds)
    cells = (math.ceil((xmax - xmin) / size) + 1) * (math.ceil((ymax - ymin) / size) + 1)
    if cells > MAX_CELLS:
        raise ValueError(f"cell {size} m gives about {cells} cells (more than {MAX_CELLS})")
    origin, shape, size = grid_frame(xmin, ymin, xmax, ymax, size)
    start, items = _build_csr(segs, origin, shape, size)
    return SegmentGrid(segs, own, origin, size, shape, start, items)


def coerce_grid(grid: SegmentGrid | None) -> SegmentGrid:
    """``grid`` with canonical field types (one compiled kernel for all callers).

    None gives :func:`empty_grid`. No copy is made when the fields are already
    C-contiguous writeable arrays of the right dtype.
    """
    if grid is None:
        return empty_grid()
    return SegmentGrid(coerce_array(grid.segments, np.float64, 2, "segments"),
                       coerce_array(grid.owner, np.int64, 1, "owner"),
                       coerce_array(grid.origin, np.float64, 1, "origin"), float(grid.cell),
                       coerce_array(grid.shape, np.int64, 1, "shape"),
                       coerce_array(grid.cell_start, np.int64, 1, "cell_start"),
                       coerce_array(grid.cell_items, np.int64, 1, "cell_items"))


def empty_grid() -> SegmentGrid:
    """A grid with no segment (one unit cell)."""
    return build_segment_grid(np.zeros((0, 4)), (0.0, 0.0, 1.0, 1.0), cell=1.0)
