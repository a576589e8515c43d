"""The walls and robots a sensor at a fixed point may see first.

A robot that stands still among neighbours that stand still keeps the same
things in sight: only headings change, and they turn its beams and its
neighbours' rectangles about fixed centres. :func:`sight_lists` lists, for
such robots, the walls and robots that some direction from the sensor may
meet first; the ranger then sweeps those alone (``still_scans.py`` decides
when the lists hold).

An item, a wall or a robot (by its bounding circle, which holds its
rectangle at any heading), is dropped when every direction that meets it
meets an occluder nearer: a piece of a wall, or a robot's inscribed circle,
which its rectangle holds at any heading. Angles are exact (libm's atan2).
Items are taken nearest first; before each, the spans of the occluders
whose farthest point is nearer than its nearest by ``DEPTH_MARGIN`` join a
union of arcs around the sensor, each drawn in by ``ANGLE_MARGIN`` at its
ends (a wall's pieces meet exactly: a beam between two pieces meets the
wall). An item whose span, widened by ``ANGLE_MARGIN``, lies inside one arc
is hidden. Every beam that could meet a hidden item then
meets an occluder clearly nearer first, so it is never a beam's nearest hit
and dropping it changes no range and no owner.

>>> segments = np.array([[2.0, -3.0, 2.0, 3.0], [4.0, -1.0, 4.0, 1.0], [4.0, 2.0, 4.0, 6.0]])
>>> walls, robots = sight_lists(0.0, 0.0, 8.0, -1, np.arange(3), segments, np.zeros(0, np.int64),
...                             np.zeros((0, 2)), np.zeros(0), np.zeros(0))
>>> walls.tolist()  # wall 1 lies behind wall 0; wall 2 shows past its end
[0, 2]
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.compiling.kernel_options import INNER
from mimics.engine.ranging.beam_sweep import PLAN
from mimics.engine.ranging.wall_index import point_segment_distance

TAU = 2.0 * math.pi
ANGLE_MARGIN = 1e-8  # rad by which an occluder's span clearly holds a beam it stops
DEPTH_MARGIN = 1e-7  # relative: how clearly an occluder is nearer than what it hides (m)
PIECE = 0.25  # m: walls occlude in pieces this long at most (a piece's far end is near)
MAX_PIECES = 64  # per wall (longer walls get longer pieces)


class SightLists(NamedTuple):
    """Per robot, the walls and robots it may see first, when ``pinned``.

    Attributes:
        pinned: ``(n,)`` bool: the robot's scan sweeps its lists instead of
            everything near it (only while it and its neighbours stand still).
        spans: ``(n, 4)`` int64: robot ``i``'s walls are
            ``items[spans[i, 0]:spans[i, 1]]`` (rows of the walls' segments), the
            robots it may see ``items[spans[i, 2]:spans[i, 3]]``.
        items: wall and robot indices.
        plan: ``(len(items), PLAN)`` float64, or no row: for each wall and robot
            listed, what the pinned robot's scans need of it whatever the headings
            (``beam_sweep.wall_plan`` and ``robot_plan``), kept while its centre does
            not move; with no rows, the scans work it out each time.
    """

    pinned: np.ndarray
    spans: np.ndarray
    items: np.ndarray
    plan: np.ndarray = np.zeros((0, PLAN))


def no_sight_lists() -> SightLists:
    """Lists pinning no robot (every scan sweeps everything near it)."""
    return SightLists(np.zeros(0, dtype=np.bool_), np.zeros((0, 4), dtype=np.int64),
                      np.zeros(0, dtype=np.int64))


@njit(**INNER)
def _span(ax: float, ay: float, bx: float, by: float) -> tuple[float, float]:
    """The counterclockwise span from ``a`` to ``b`` (the shorter way round) seen from the
    origin: ``low`` in ``[-pi, pi]`` and ``high >= low``; ``high`` is -inf when the
    origin is on their line."""
    cross = ax * by - ay * bx
    if cross * cross <= 1e-18 * (ax * ax + ay * ay) * (bx * bx + by * by):
        return 0.0, -math.inf
    low, high = math.atan2(ay, ax), math.atan2(by, bx)
    if cross < 0.0:
        low, high = high, low
    return low, high + TAU if high < low else high


@njit(**INNER)
def _around(segments: np.ndarray, s: int, ox: float,
            oy: float) -> tuple[float, float, float, float]:
    """Wall ``s``'s ends relative to the sensor at ``(ox, oy)``."""
    return segments[s, 0] - ox, segments[s, 1] - oy, segments[s, 2] - ox, segments[s, 3] - oy


@njit(**INNER)
def _add(arcs: np.ndarray, count: int, low: float, high: float) -> int:
    """Merge ``[low, high]`` (within ``[0, 2 pi]``) into the sorted, disjoint arcs
    ``arcs[:, :count]``; returns their new count. Arcs that touch merge: pieces of one
    wall share their ends exactly."""
    kept = 0
    for k in range(count):
        if arcs[1, k] < low or arcs[0, k] > high:
            arcs[0, kept], arcs[1, kept] = arcs[0, k], arcs[1, k]
            kept += 1
        else:
            low, high = smaller(low, arcs[0, k]), larger(high, arcs[1, k])
    at = kept
    while at > 0 and arcs[0, at - 1] > low:
        arcs[0, at], arcs[1, at] = arcs[0, at - 1], arcs[1, at - 1]
        at -= 1
    arcs[0, at], arcs[1, at] = low, high
    return kept + 1


@njit(**INNER)
def _cover(arcs: np.ndarray, count: int, start: float, width: float) -> int:
    """Add the span ``[start, start + width]`` to the arcs (split where it wraps)."""
    low = start % TAU
    high = low + width
    if high > TAU:
        count = _add(arcs, count, 0.0, high - TAU)
        high = TAU
    return _add(arcs, count, low, high)


@njit(**INNER)
def _inside(arcs: np.ndarray, count: int, low: float, high: float) -> bool:
    for k in range(count):  # noqa: SIM110 (a loop compiles; any() over a generator does not)
        if arcs[0, k] <= low and high <= arcs[1, k]:
            return True
    return False


@njit(**INNER)
def _covered(arcs: np.ndarray, count: int, start: float, width: float) -> bool:
    """Whether the arcs hold the whole span ``[start, start + width]``."""
    if width >= TAU:
        return False
    low = start % TAU
    high = low + width
    if high > TAU:
        return _inside(arcs, count, 0.0, high - TAU) and _inside(arcs, count, low, TAU)
    return _inside(arcs, count, low, high)


@njit(cache=True)
def sight_lists(ox: float, oy: float, limit: float, me: int, walls: np.ndarray,
                segments: np.ndarray, robots: np.ndarray, centers: np.ndarray,
                radius: np.ndarray, inner: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The walls (of ``walls``) and robots (of ``robots``, less ``me``) that a sensor at
    ``(ox, oy)`` with range ``limit`` may see first.

    ``segments`` are the walls' ``x1, y1, x2, y2``; ``centers``, ``radius`` and
    ``inner`` every robot's centre, bounding and inscribed radius. Items wholly
    beyond ``limit`` are dropped too.
    """
    nw, nr = walls.shape[0], robots.shape[0]
    # items: walls, then robots; nearest distance, span start and width (-1: never hidden)
    near = np.empty(nw + nr)
    start = np.empty(nw + nr)
    width = np.empty(nw + nr)
    pieces = np.zeros(nw, dtype=np.int64)  # how many pieces each wall occludes in
    for p in range(nw):
        x1, y1, x2, y2 = _around(segments, walls[p], ox, oy)
        near[p] = point_segment_distance(0.0, 0.0, x1, y1, x2, y2)
        low, high = _span(x1, y1, x2, y2)
        start[p], width[p] = low, larger(high - low, -1.0)
        if width[p] >= 0.0:
            pieces[p] = smaller(MAX_PIECES,
                                larger(1, math.ceil(math.hypot(x2 - x1, y2 - y1) / PIECE)))
    # occluders: robots' inscribed circles and pieces of walls; span and farthest point
    total = nr + np.sum(pieces)
    depth = np.empty(total)
    o_start = np.empty(total)
    o_width = np.empty(total)
    count = 0
    for p in range(nr):
        r = robots[p]
        cx, cy = centers[r, 0] - ox, centers[r, 1] - oy
        distance = math.sqrt(cx * cx + cy * cy)
        near[nw + p] = distance - radius[r]
        width[nw + p] = -1.0
        if r == me:
            continue
        if distance > radius[r] * (1.0 + 1e-9):
            half = math.asin(radius[r] / distance)
            start[nw + p], width[nw + p] = math.atan2(cy, cx) - half, 2.0 * half
        if distance > inner[r] * (1.0 + 1e-9):
            # a beam within asin(inner / distance) of the centre meets the circle nearer
            # than the centre, and the rectangle holding the circle no farther
            half = math.asin(inner[r] / distance) - ANGLE_MARGIN
            o_start[count], o_width[count] = math.atan2(cy, cx) - half, 2.0 * half
            depth[count] = distance
            count += 1
    for p in range(nw):
        x1, y1, x2, y2 = _around(segments, walls[p], ox, oy)
        m = pieces[p]
        # pieces of one wall meet exactly (a beam between them meets the wall); only the
        # wall's own ends are drawn in, where a beam may slip past it
        first = start[p] + ANGLE_MARGIN
        last = start[p] + width[p] - ANGLE_MARGIN
        for k in range(m):
            # the piece's ends lie on the wall up to rounding, far below ANGLE_MARGIN
            ax, ay = x1 + (x2 - x1) * (k / m), y1 + (y2 - y1) * (k / m)
            bx, by = x1 + (x2 - x1) * ((k + 1) / m), y1 + (y2 - y1) * ((k + 1) / m)
            low, high = _span(ax, ay, bx, by)
            if high < low:
                continue
            # the piece's span, unwrapped next to the wall's, clipped to its drawn-in one
            shift = TAU * round((start[p] - low) / TAU)
            low, high = larger(low + shift, first), smaller(high + shift, last)
            o_start[count], o_width[count] = low, high - low
            depth[count] = larger(math.sqrt(ax * ax + ay * ay), math.sqrt(bx * bx + by * by))
            # a piece farther than the range could only hide what lies beyond it
            count += depth[count] <= limit
    # nearest items first, each against the occluders clearly nearer than it
    arcs = np.empty((2, 2 * count + 2))
    arcs_count = 0
    by_depth = np.argsort(depth[:count])
    used = 0
    kept_walls = np.empty(nw, dtype=np.int64)
    kept_robots = np.empty(nr, dtype=np.int64)
    kw = kr = 0
    for p in np.argsort(near):
        if near[p] > limit * (1.0 + 1e-9) + 1e-9 or (p >= nw and robots[p - nw] == me):
            continue
        clear = near[p] - DEPTH_MARGIN * (1.0 + near[p])
        while used < count and depth[by_depth[used]] < clear:
            o = by_depth[used]
            if o_width[o] > 0.0:
                arcs_count = _cover(arcs, arcs_count, o_start[o], o_width[o])
            used += 1
        if width[p] >= 0.0 and _covered(arcs, arcs_count, start[p] - ANGLE_MARGIN,
                                        width[p] + 2.0 * ANGLE_MARGIN):
            continue
        if p < nw:
            kept_walls[kw] = walls[p]
            kw += 1
        else:
            kept_robots[kr] = robots[p - nw]
            kr += 1
    return np.sort(kept_walls[:kw]), np.sort(kept_robots[:kr])
