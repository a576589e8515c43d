"""Exact collisions of robot rectangles with walls and with each other.

A robot collides when its closed rectangle touches a wall segment (they
cross, or the segment lies inside) or the rectangle of another solid robot
(edges cross, or one contains the other). Contact is decided up to
``TOUCH_EPS`` (1 nm): boundary contact counts even when rounding of the
rotated corners lands a hair away, and a gap of 1e-6 m is never a collision.

Candidates come from the grids: wall segments in the cells under a robot's
bounding box, and solid robots whose bounding circle meets its own (from the
robot index's cells within reach), so that a small robot entirely inside a
big one, touching none of its edges, is found too.
Robots are checked one after another, each from its own inputs only: a parallel
loop compiled ~2 s slower and ran no faster (about 0.1 ms a step for 100 robots).

>>> import numpy as np
>>> from mimics.engine.robot_index import build_robot_index
>>> from mimics.engine.spatial_index import build_segment_grid
>>> bodies = Bodies(np.array([[0.0, 0.0], [1.5, 0.0], [5.0, 0.0]]), np.zeros(3),
...                 np.full(3, 0.5), np.full(3, 0.5))
>>> walls = build_segment_grid(np.array([[5.5, -1.0, 5.5, 1.0]]), (-2, -2, 7, 2))
>>> solid = np.ones(3, dtype=bool)
>>> robots = build_robot_index(*bodies, solid)
>>> with_whom, wall = find_collisions(bodies, solid, solid, walls, robots)
>>> with_whom.tolist(), wall.tolist()
([-2, -2, -1], [-1, -1, 0])
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_options import INNER
from mimics.engine.robot_index import RobotIndex, build_robot_index, coerce_robot_index
from mimics.engine.spatial_index import (
    SegmentGrid,
    cell_span,
    clip_to_slab,
    coerce_array,
    coerce_grid,
    grid_pad,
)

NONE = -2  # with_whom of a robot that touches nothing
WALL = -1  # with_whom of a robot that touches only walls
TOUCH_EPS = 1e-9  # contact tolerance (m)


class Bodies(NamedTuple):
    """Robot rectangles, one row per robot.

    Attributes:
        centers: ``(n, 2)`` centres.
        headings: ``(n,)`` headings (rad); the length lies along the heading.
        half_length: ``(n,)`` half sizes along the heading.
        half_width: ``(n,)`` half sizes across it.
    """

    centers: np.ndarray
    headings: np.ndarray
    half_length: np.ndarray
    half_width: np.ndarray


@njit(**INNER)
def segment_touches_box(x1: float, y1: float, x2: float, y2: float, hx: float,
                        hy: float) -> bool:
    """Whether a segment touches the closed box ``[-hx, hx] x [-hy, hy]`` (Liang-Barsky).

    Args:
        x1: first end x, in the box's frame.
        y1: first end y.
        x2: second end x.
        y2: second end y.
        hx: half size along x.
        hy: half size along y.

    Returns:
        True when some point of the segment lies in the box.
    """
    s0, s1 = clip_to_slab(x1, x2 - x1, -hx, hx, 0.0, 1.0)
    s0, s1 = clip_to_slab(y1, y2 - y1, -hy, hy, s0, s1)
    return s0 <= s1


@njit(**INNER)
def boxes_touch(ax: float, ay: float, ah: float, al: float, aw: float, bx: float, by: float,
                bh: float, bl: float, bw: float, eps: float) -> bool:
    """Whether two oriented rectangles are within ``eps`` on all four separating axes.

    Separating-axis test: two convex polygons are disjoint exactly when their
    projections on some edge normal are disjoint; it covers containment.

    Args:
        ax: centre x of the first rectangle.
        ay: centre y of the first rectangle.
        ah: its heading.
        al: its half length (along the heading).
        aw: its half width.
        bx: centre x of the second rectangle.
        by: centre y of the second rectangle.
        bh: its heading.
        bl: its half length.
        bw: its half width.
        eps: gap still counted as contact (m).

    Returns:
        True when no axis separates them by more than ``eps``.
    """
    ca, sa = math.cos(ah), math.sin(ah)
    cb, sb = math.cos(bh), math.sin(bh)
    tx, ty = bx - ax, by - ay
    for k in range(4):
        if k == 0:
            nx, ny = ca, sa
        elif k == 1:
            nx, ny = -sa, ca
        elif k == 2:
            nx, ny = cb, sb
        else:
            nx, ny = -sb, cb
        ra = al * abs(ca * nx + sa * ny) + aw * abs(-sa * nx + ca * ny)
        rb = bl * abs(cb * nx + sb * ny) + bw * abs(-sb * nx + cb * ny)
        if abs(tx * nx + ty * ny) > ra + rb + eps:
            return False
    return True


@njit(**INNER, inline="always")
def _lowest_wall(b: Bodies, i: int, walls: SegmentGrid) -> int:
    """Lowest index of a wall segment touching robot ``i``, or -1."""
    cx, cy = b.centers[i, 0], b.centers[i, 1]
    c, s = math.cos(b.headings[i]), math.sin(b.headings[i])
    hl, hw = b.half_length[i], b.half_width[i]
    margin = TOUCH_EPS + grid_pad(walls.origin, walls.shape, walls.cell)
    ex = hl * abs(c) + hw * abs(s) + margin  # bounding-box half sizes
    ey = hl * abs(s) + hw * abs(c) + margin
    nx, ny = walls.shape[0], walls.shape[1]
    ix0, ix1 = cell_span(cx - ex, cx + ex, walls.origin[0], walls.cell, nx)
    iy0, iy1 = cell_span(cy - ey, cy + ey, walls.origin[1], walls.cell, ny)
    best = -1
    segs = walls.segments
    for iy in range(iy0, iy1 + 1):
        for ix in range(ix0, ix1 + 1):
            cid = iy * nx + ix
            for p in range(walls.cell_start[cid], walls.cell_start[cid + 1]):
                k = walls.cell_items[p]
                if best >= 0 and k >= best:
                    continue
                # the segment in the robot's frame, against its padded box
                x1, y1 = segs[k, 0] - cx, segs[k, 1] - cy
                x2, y2 = segs[k, 2] - cx, segs[k, 3] - cy
                if segment_touches_box(x1 * c + y1 * s, -x1 * s + y1 * c, x2 * c + y2 * s,
                                       -x2 * s + y2 * c, hl + TOUCH_EPS, hw + TOUCH_EPS):
                    best = k
    return best


@njit(**INNER, inline="always")
def _lowest_robot(b: Bodies, i: int, robots: RobotIndex) -> int:
    """Lowest index of a visible (solid) robot touching robot ``i``, or -1."""
    cx, cy = b.centers[i, 0], b.centers[i, 1]
    h = b.headings[i]
    hl, hw = b.half_length[i], b.half_width[i]
    # bounding circles that touch: centres at most the two radii apart
    own = math.hypot(hl, hw)
    reach = own + robots.max_radius + TOUCH_EPS
    nx = robots.shape[0]
    ix0, ix1 = cell_span(cx - reach, cx + reach, robots.origin[0], robots.cell, nx)
    iy0, iy1 = cell_span(cy - reach, cy + reach, robots.origin[1], robots.cell, robots.shape[1])
    best = -1
    for iy in range(iy0, iy1 + 1):
        for ix in range(ix0, ix1 + 1):
            c = iy * nx + ix
            for p in range(robots.grid_start[c], robots.grid_start[c + 1]):
                j = robots.grid_items[p]
                if j == i or (best >= 0 and j >= best):
                    continue
                gap = math.hypot(robots.centers[j, 0] - cx, robots.centers[j, 1] - cy)
                if gap > own + robots.radius[j] + TOUCH_EPS:
                    continue
                if boxes_touch(cx, cy, h, hl, hw, b.centers[j, 0], b.centers[j, 1],
                               b.headings[j], b.half_length[j], b.half_width[j], TOUCH_EPS):
                    best = j
    return best


# touching and the two searches are inlined into the kernels that call them: a call
# reference-counts each array of the Bodies, SegmentGrid and RobotIndex it takes (17),
# 130 to 200 ns a robot, a quarter to a third of a check (check_moved of 10,000 robots
# on 2 threads: 3.2 -> 1.8 ms)
@njit(cache=True, inline="always")
def touching(b: Bodies, i: int, walls: SegmentGrid, robots: RobotIndex) -> tuple[int, int]:
    """What robot ``i`` touches: ``with_whom`` (as :func:`find_collisions` gives it) and
    the lowest touching wall segment (-1 for none)."""
    wall = _lowest_wall(b, i, walls)
    other = _lowest_robot(b, i, robots)
    if other >= 0:
        return other, wall
    return (WALL if wall >= 0 else NONE), wall


@njit(cache=True)
def _collide_kernel(bodies: tuple, check: np.ndarray, wall_grid: tuple, robot_index: tuple,
                    with_whom: np.ndarray, wall_segment: np.ndarray) -> None:
    """Fill ``with_whom`` and ``wall_segment`` for every checked robot.

    ``bodies``, ``wall_grid`` and ``robot_index``: the fields of a ``Bodies``,
    ``SegmentGrid`` and ``RobotIndex`` as plain tuples (``tuple(grid)``), since
    Numba's dispatcher types a plain tuple of arrays in C but a named one in
    Python: about 7 us less per call, which a step of few robots notices.
    """
    b, walls, robots = Bodies(*bodies), SegmentGrid(*wall_grid), RobotIndex(*robot_index)
    for i in range(check.shape[0]):
        with_whom[i] = NONE
        wall_segment[i] = -1
        if check[i]:
            with_whom[i], wall_segment[i] = touching(b, i, walls, robots)


def _as_bodies(bodies: Bodies) -> Bodies:
    centers = coerce_array(bodies.centers, np.float64, 2, "centers")
    n = len(centers)
    b = Bodies(centers, coerce_array(bodies.headings, np.float64, 1, "headings"),
               coerce_array(np.broadcast_to(bodies.half_length, (n,)), np.float64, 1,
                         "half_length"),
               coerce_array(np.broadcast_to(bodies.half_width, (n,)), np.float64, 1,
                         "half_width"))
    if centers.shape != (n, 2) or len(b.headings) != n:
        raise ValueError("centers must be (n, 2) and headings (n,)")
    return b


def find_collisions(bodies: Bodies, check: np.ndarray, solid: np.ndarray,
                    walls: SegmentGrid,
                    robots: RobotIndex | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Which checked robots touch a wall or another solid robot.

    A robot touching both a robot and a wall is reported as touching the
    robot (``with_whom``); ``wall_segment`` still names the wall.

    Args:
        bodies: all robots' rectangles.
        check: ``(n,)`` bool, robots to check.
        solid: ``(n,)`` bool, robots that others can touch.
        walls: grid of wall segments (a ``WallIndex.grid``).
        robots: index of the solid robots, built from the same ``bodies`` and
            ``solid`` by ``build_robot_index``; None builds it here.

    Returns:
        ``with_whom (n,)`` int64: -2 touches nothing (or not checked), -1
        touches only walls, ``j >= 0`` the lowest index of a touching solid
        robot ``j != i``; ``wall_segment (n,)`` int64: the lowest index of a
        touching wall segment, or -1.

    Raises:
        ValueError: mismatched shapes or non-finite poses of checked or
            solid robots.
    """
    b = _as_bodies(bodies)
    n = len(b.centers)
    chk = coerce_array(np.broadcast_to(check, (n,)), np.bool_, 1, "check")
    sol = coerce_array(np.broadcast_to(solid, (n,)), np.bool_, 1, "solid")
    used = chk | sol
    if not (np.all(np.isfinite(b.centers[used])) and np.all(np.isfinite(b.headings[used]))):
        raise ValueError("checked and solid robots must have finite poses")
    if robots is None:
        robots = build_robot_index(b.centers, b.headings, b.half_length, b.half_width, sol)
    return collide(b, chk, coerce_grid(walls), coerce_robot_index(robots))


def collide(bodies: Bodies, check: np.ndarray, walls: SegmentGrid,
            robots: RobotIndex) -> tuple[np.ndarray, np.ndarray]:
    """:func:`find_collisions` without the checks, for the engine's own arrays.

    ``bodies`` and ``check`` must be C-contiguous float64 and bool arrays with
    finite poses; ``walls`` and ``robots`` as the kernels take them.
    """
    n = len(bodies.centers)
    if n and check.shape[0] == n:  # the kernel writes every entry: no filling first
        with_whom, wall_segment = np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64)
    else:
        with_whom = np.full(n, NONE, dtype=np.int64)
        wall_segment = np.full(n, -1, dtype=np.int64)
    if n:
        _collide_kernel(tuple(bodies), check, tuple(walls), tuple(robots), with_whom,
                        wall_segment)
    return with_whom, wall_segment
