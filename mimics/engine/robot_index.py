"""Robots that sensors can see, bucketed by centre (rebuilt every step).

A :class:`RobotIndex` holds the corners of every visible robot's rectangle
and a coarse grid of robot indices by centre. The ranger finds the robots
within a beam's range by visiting the few cells around the sensor and
checking each robot's bounding circle; only robots that pass are traced.
Building costs O(n + cells) in one compiled pass.

>>> idx = build_robot_index(np.array([[0.0, 0.0], [3.0, 0.0]]), np.zeros(2), 0.5, 0.25,
...                         np.array([True, False]), cell=1.0)
>>> idx.grid_items.tolist(), idx.corners[0, 0].tolist()  # robot 1 is not visible
([0], [0.5, 0.25])
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.compiling.kernel_options import INNER
from mimics.engine.spatial_index import cell_span, coerce_array, grid_frame

MAX_CELLS_PER_ROBOT = 4  # the grid never has more than 4 n + 1024 cells


class RobotIndex(NamedTuple):
    """Visible robots' rectangles and a grid of their centres (read-only).

    Attributes:
        corners: ``(n, 5, 2)`` corners front-left, rear-left, rear-right,
            front-right and front-left again: edge ``e`` runs from corner
            ``e`` to ``e + 1`` (left, rear, right, front side).
        radius: ``(n,)`` half-diagonals (the bounding circles' radii).
        centers: ``(n, 2)`` centres.
        origin: ``(2,)`` lower-left corner of the grid.
        cell: side of a cell (m).
        shape: ``(2,)`` int64 ``nx, ny``.
        grid_start: ``(nx * ny + 1,)`` CSR offsets into ``grid_items``.
        grid_items: visible robots' indices, cell after cell.
        max_radius: the largest radius among visible robots (0 if none).
    """

    corners: np.ndarray
    radius: np.ndarray
    centers: np.ndarray
    origin: np.ndarray
    cell: float
    shape: np.ndarray
    grid_start: np.ndarray
    grid_items: np.ndarray
    max_radius: float


def _robot_arrays(centers: np.ndarray, headings: np.ndarray, half_length: np.ndarray,
                  half_width: np.ndarray, include: np.ndarray) -> tuple[np.ndarray, ...]:
    c = coerce_array(centers, np.float64, 2, "centers")
    n = len(c)
    out = [c, coerce_array(headings, np.float64, 1, "headings"),
           coerce_array(np.broadcast_to(half_length, (n,)), np.float64, 1, "half_length"),
           coerce_array(np.broadcast_to(half_width, (n,)), np.float64, 1, "half_width"),
           coerce_array(np.broadcast_to(include, (n,)), np.bool_, 1, "include")]
    if c.shape != (n, 2) or len(out[1]) != n:
        raise ValueError("centers must be (n, 2) and headings (n,)")
    return tuple(out)


@njit(**INNER, inline="always")
def _fill_corners(centers: np.ndarray, headings: np.ndarray, half_length: np.ndarray,
                  half_width: np.ndarray, out: np.ndarray) -> None:
    """Rectangle corners into ``out`` (the order is that of ``RobotIndex.corners``)."""
    for i in range(centers.shape[0]):
        c = math.cos(headings[i])
        s = math.sin(headings[i])
        ux, uy = half_length[i] * c, half_length[i] * s
        vx, vy = -half_width[i] * s, half_width[i] * c
        cx, cy = centers[i, 0], centers[i, 1]
        out[i, 0, 0], out[i, 0, 1] = cx + ux + vx, cy + uy + vy
        out[i, 1, 0], out[i, 1, 1] = cx - ux + vx, cy - uy + vy
        out[i, 2, 0], out[i, 2, 1] = cx - ux - vx, cy - uy - vy
        out[i, 3, 0], out[i, 3, 1] = cx + ux - vx, cy + uy - vy
        out[i, 4, 0], out[i, 4, 1] = out[i, 0, 0], out[i, 0, 1]


@njit(cache=True)
def _bucket(centers: np.ndarray, headings: np.ndarray, half_length: np.ndarray,
            half_width: np.ndarray, radius: np.ndarray, include: np.ndarray, cell_hint: float
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, np.ndarray, np.ndarray, float]:
    """The whole index in one call (a call costs more than the work for a few robots):
    every robot's corners, a grid over the included centres (counting sort into
    cells) and the largest included radius."""
    n = centers.shape[0]
    corners = np.empty((n, 5, 2))
    _fill_corners(centers, headings, half_length, half_width, corners)
    k = 0
    max_radius = 0.0
    xmin, ymin, xmax, ymax = math.inf, math.inf, -math.inf, -math.inf
    for i in range(n):
        if include[i]:
            k += 1
            max_radius = larger(max_radius, radius[i])
            xmin, xmax = smaller(xmin, centers[i, 0]), larger(xmax, centers[i, 0])
            ymin, ymax = smaller(ymin, centers[i, 1]), larger(ymax, centers[i, 1])
    if k == 0:
        xmin, ymin, xmax, ymax = 0.0, 0.0, 1.0, 1.0
    w, h = xmax - xmin, ymax - ymin
    cell = larger(cell_hint, math.sqrt(w * h / (MAX_CELLS_PER_ROBOT * k + 1024)),
               larger(w, h) / 65536.0, 1e-9)
    origin, shape, cell = grid_frame(xmin, ymin, xmax, ymax, cell)
    nx, ny = shape[0], shape[1]
    start = np.zeros(nx * ny + 1, dtype=np.int64)
    where = np.empty(n, dtype=np.int64)
    for i in range(n):
        if include[i]:
            ix = smaller(larger(int((centers[i, 0] - origin[0]) / cell), 0), nx - 1)
            iy = smaller(larger(int((centers[i, 1] - origin[1]) / cell), 0), ny - 1)
            where[i] = iy * nx + ix
            start[where[i] + 1] += 1
    for c in range(nx * ny):
        start[c + 1] += start[c]
    items = np.empty(k, dtype=np.int64)
    cursor = start[: nx * ny].copy()
    for i in range(n):
        if include[i]:
            items[cursor[where[i]]] = i
            cursor[where[i]] += 1
    return corners, origin, shape, cell, start, items, max_radius


@njit(**INNER, inline="always")
def robots_near(index: RobotIndex, x: float, y: float, span: float, out: np.ndarray) -> int:
    """Put in ``out`` the robots of the cells that come within ``span`` of ``(x, y)``
    along each axis; returns how many (the ranger's candidates, before their circles)."""
    nx = index.shape[0]
    ix0, ix1 = cell_span(x - span, x + span, index.origin[0], index.cell, nx)
    iy0, iy1 = cell_span(y - span, y + span, index.origin[1], index.cell, index.shape[1])
    found = 0
    for iy in range(iy0, iy1 + 1):  # the cells of a row are contiguous in the CSR
        for p in range(index.grid_start[iy * nx + ix0], index.grid_start[iy * nx + ix1 + 1]):
            out[found] = index.grid_items[p]
            found += 1
    return found


def index_cell(max_range: np.ndarray, half_length: np.ndarray,
               half_width: np.ndarray) -> float:
    """The grid cell for robots with these rangers and sizes: half the longest
    range, so that a sensor visits about 5 x 5 cells and a collision check 1 to
    4, but at least four robot half-diagonals."""
    reach = float(np.max(max_range, initial=0.0))
    largest = float(np.max(np.hypot(half_length, half_width), initial=0.0))
    return max(reach / 2, 4 * largest, 1e-3)


def build_robot_index(centers: np.ndarray, headings: np.ndarray, half_length: np.ndarray,
                      half_width: np.ndarray, include_mask: np.ndarray,
                      cell: float = 1.0) -> RobotIndex:
    """Index the included robots (those others can see).

    Args:
        centers: ``(n, 2)`` rectangle centres.
        headings: ``(n,)`` headings (rad).
        half_length: ``(n,)`` half sizes along the heading (or a scalar).
        half_width: ``(n,)`` half sizes across it (or a scalar).
        include_mask: ``(n,)`` bool, robots that sensors can see.
        cell: grid cell (m); about half the longest sensor range keeps the
            cells visited per sensor few. Grown when the grid would have more
            than ``4 n + 1024`` cells.

    Returns:
        The index (corners are computed for every robot, included or not).

    Raises:
        ValueError: mismatched shapes, non-finite poses of included robots or
            a non-positive cell.
    """
    c, h, hl, hw, inc = _robot_arrays(centers, headings, half_length, half_width, include_mask)
    if not (np.all(np.isfinite(c[inc])) and np.all(np.isfinite(h[inc]))):
        raise ValueError("included robots must have finite poses")
    if not (math.isfinite(cell) and cell > 0):
        raise ValueError(f"cell must be a positive number, got {cell!r}")
    return index_robots(c, h, hl, hw, inc, float(cell))


def index_robots(centers: np.ndarray, headings: np.ndarray, half_length: np.ndarray,
                 half_width: np.ndarray, include: np.ndarray, cell: float,
                 radius: np.ndarray | None = None) -> RobotIndex:
    """:func:`build_robot_index` without the checks, for the engine's own arrays.

    The arrays must be C-contiguous float64 (``include`` bool), of matching
    lengths, with finite poses where ``include`` is set, and ``cell > 0``.
    ``radius``: ``np.hypot(half_length, half_width)`` when the caller keeps it
    (sizes do not change during a run).
    """
    if radius is None:
        radius = np.hypot(half_length, half_width)
    corners, origin, shape, size, start, items, max_radius = _bucket(
        centers, headings, half_length, half_width, radius, include, cell)
    return RobotIndex(corners, radius, centers, origin, size, shape, start, items, max_radius)


def empty_robot_index() -> RobotIndex:
    """An index with no robot."""
    none = np.zeros(0)
    return build_robot_index(np.zeros((0, 2)), none, none, none, np.zeros(0, bool))


def coerce_robot_index(index: RobotIndex | None) -> RobotIndex:
    """``index`` with canonical field types; None gives an empty index."""
    if index is None:
        return empty_robot_index()
    return RobotIndex(coerce_array(index.corners, np.float64, 3, "corners"),
                      coerce_array(index.radius, np.float64, 1, "radius"),
                      coerce_array(index.centers, np.float64, 2, "centers"),
                      coerce_array(index.origin, np.float64, 1, "origin"), float(index.cell),
                      coerce_array(index.shape, np.int64, 1, "shape"),
                      coerce_array(index.grid_start, np.int64, 1, "grid_start"),
                      coerce_array(index.grid_items, np.int64, 1, "grid_items"),
                      float(index.max_radius))
