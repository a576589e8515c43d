"""A segment swept over the beams it spans; a robot by its sides; the fine-grid walk.

The ray kernel (:mod:`mimics.engine.ranging.ranger`) sweeps the walls and robots near
a sensor, nearest first: each segment is tested against the beams its angular
span covers (:mod:`mimics.engine.ranging.beam_fan`), four beams at a time without
branches, and blocks whose farthest hit is nearer than the segment are
skipped. Beyond the sweep's reach, a beam walks the fine walls grid cell by
cell (Amanatides-Woo). The geometry's rules are in :mod:`mimics.engine.ranging.ranger`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.compiling.kernel_options import INNER
from mimics.engine.ranging.beam_fan import (
    COLLINEAR_EPS,
    TAU,
    Layout,
    _beam_range,
    _relative,
    _turn,
    _turns,
    fast_atan2,
)
from mimics.engine.ranging.wall_index import point_segment_distance
from mimics.engine.spatial_index import SegmentGrid, clip_to_slab

NO_HIT = -2  # hit_owner of a beam that hit nothing within range


WALL = -1  # hit_owner of a beam that hit a wall


PARALLEL_EPS = 1e-12  # |sin| of the beam-segment angle below which they are parallel




ANGLE_EPS = 1e-9  # sin of the angle a segment spans below which all beams test it


# beams per block whose farthest hit so far lets a segment skip them all; on the Cave,
# blocks of 2, 8 and 16 are 7%, 9% and 25% slower
BLOCK = 4


# rows of a scan's work array (one array: every array an inlined helper takes is
# reference-counted at each call); FAR holds one entry per block of beams
DX, DY, NEAR, FAR = 0, 1, 2, 3


@njit(cache=True)
def ray_segment_distance(ox: float, oy: float, dx: float, dy: float, x1: float, y1: float,
                         x2: float, y2: float) -> float:
    """Distance along the unit ray ``(ox, oy) + t (dx, dy)`` to a segment; inf if missed.

    Args:
        ox: ray origin x.
        oy: ray origin y.
        dx: unit direction x.
        dy: unit direction y.
        x1: first end x.
        y1: first end y.
        x2: second end x.
        y2: second end y.

    Returns:
        The smallest ``t >= 0`` on the segment, or ``inf``.
    """
    ex, ey = x2 - x1, y2 - y1
    wx, wy = x1 - ox, y1 - oy
    denom = dx * ey - dy * ex  # d x e
    num_t = wx * ey - wy * ex  # w x e
    num_u = wx * dy - wy * dx  # w x d: signed distance of the first end to the beam's line
    if abs(denom) > PARALLEL_EPS * (abs(ex) + abs(ey)):
        if denom < 0:
            denom, num_t, num_u = -denom, -num_t, -num_u
        # compare numerators: no division rounding in the inside/outside decision
        if num_t >= 0 and 0 <= num_u <= denom:
            return num_t / denom
        return math.inf
    # parallel (or a point): a hit only if both ends lie on the beam's line
    if abs(num_u) > COLLINEAR_EPS or abs(num_u - denom) > COLLINEAR_EPS:
        return math.inf
    tp = wx * dx + wy * dy
    tq = (x2 - ox) * dx + (y2 - oy) * dy
    near, far = smaller(tp, tq), larger(tp, tq)
    if far < 0:
        return math.inf
    return larger(near, 0.0)


@njit(**INNER)
def _cell_exit(grid_start: float, index: int, cell: float, origin: float,
               delta: float) -> float:
    """Ray parameter where it leaves cell ``index`` of one grid axis (inf if parallel)."""
    if delta > 0:
        return (grid_start + (index + 1) * cell - origin) / delta
    if delta < 0:
        return (grid_start + index * cell - origin) / delta
    return math.inf


@njit(**INNER)
def _trace(grid: SegmentGrid, ox: float, oy: float, dx: float, dy: float, limit: float,
           me: int, best_t: float, best_o: int, start: float = 0.0) -> tuple[float, int]:
    """Improve ``(best_t, best_o)`` with the segments of ``grid`` hit in ``[start, limit]``.

    The walk starts in the cell holding the ray's point at ``start``: hits
    nearer than that must already be in ``best_t``.
    """
    if grid.segments.shape[0] == 0:
        return best_t, best_o
    gx, gy, c = grid.origin[0], grid.origin[1], grid.cell
    nx, ny = grid.shape[0], grid.shape[1]
    # clip the ray's [start, limit] to the grid box: it may start outside
    t0, t1 = clip_to_slab(ox, dx, gx, gx + nx * c, start, limit)
    t0, t1 = clip_to_slab(oy, dy, gy, gy + ny * c, t0, t1)
    if t0 > t1:
        return best_t, best_o
    ix = int(smaller(larger(math.floor((ox + t0 * dx - gx) / c), 0.0), nx - 1.0))
    iy = int(smaller(larger(math.floor((oy + t0 * dy - gy) / c), 0.0), ny - 1.0))
    step_x = 1 if dx > 0 else -1
    step_y = 1 if dy > 0 else -1
    segs, owner = grid.segments, grid.owner
    for _ in range(nx + ny):  # a ray crosses at most nx + ny - 1 cells
        # exit distances recomputed from the cell index: no drift along long rays
        tx = _cell_exit(gx, ix, c, ox, dx)
        ty = _cell_exit(gy, iy, c, oy, dy)
        cid = iy * nx + ix
        for p in range(grid.cell_start[cid], grid.cell_start[cid + 1]):
            s = grid.cell_items[p]
            o = owner[s]
            if o >= 0 and o == me:
                continue
            t = ray_segment_distance(ox, oy, dx, dy, segs[s, 0], segs[s, 1], segs[s, 2],
                                     segs[s, 3])
            if t <= limit and (t < best_t or (t == best_t and o < best_o)):
                best_t, best_o = t, o
        t_exit = smaller(tx, ty)
        # farther cells only hold hits beyond t_exit (segments near a cell side
        # are listed on both sides of it, see grid_pad)
        if best_t <= t_exit or t_exit >= limit:
            break
        if tx < ty:
            ix += step_x
            if ix < 0 or ix >= nx:
                break
        else:
            iy += step_y
            if iy < 0 or iy >= ny:
                break
    return best_t, best_o


@njit(**INNER)
def _consider(ox: float, oy: float, work: np.ndarray, j: int, x1: float, y1: float,
              x2: float, y2: float, o: int, limit: float, best_o: np.ndarray) -> None:
    """Let segment ``(x1, y1, x2, y2)`` of owner ``o`` improve beam ``j``'s hit."""
    t = ray_segment_distance(ox, oy, work[DX, j], work[DY, j], x1, y1, x2, y2)
    if t <= limit and (t < work[NEAR, j] or (t == work[NEAR, j] and o < best_o[j])):
        work[NEAR, j] = t
        best_o[j] = o


@njit(**INNER)
def _below(distance: float) -> float:
    """A distance shrunk past rounding: beams hitting nearer than it surely skip a segment."""
    return distance - 1e-9 * (1.0 + distance)


@njit(**INNER)
def _sweep_block(start: int, ox: float, oy: float, x1: float, y1: float, x2: float, y2: float,
                 o: int, limit: float, work: np.ndarray, best_o: np.ndarray) -> float:
    """Let one segment improve the ``BLOCK`` beams from ``start``; their farthest hit after.

    The same arithmetic as :func:`ray_segment_distance`, hence the same bits,
    but with selects instead of branches: whether a beam hits is as good as
    random, and a mispredicted branch costs more than the arithmetic. Beams
    that meet the segment parallel (rare) go through it one by one.
    """
    ex, ey = x2 - x1, y2 - y1
    wx, wy = x1 - ox, y1 - oy
    num_t = wx * ey - wy * ex
    parallel = PARALLEL_EPS * (abs(ex) + abs(ey))
    any_parallel = False
    # plain indices, no slices: a slice is a new array whose reference counting would
    # cost more than the block's arithmetic
    for j in range(start, start + BLOCK):
        dx, dy = work[DX, j], work[DY, j]
        denom = dx * ey - dy * ex
        num_u = wx * dy - wy * dx
        sign = math.copysign(1.0, denom)  # exact: as swapping the signs
        crossing = abs(denom) > parallel
        any_parallel |= not crossing
        inside = (num_t * sign >= 0.0) & (num_u * sign >= 0.0) & (num_u * sign <= denom * sign)
        ratio = num_t / denom  # every lane divides: no branch (needs error_model="numpy")
        t = ratio if crossing & inside else math.inf
        kept_t, kept_o = work[NEAR, j], best_o[j]
        better = (t <= limit) & ((t < kept_t) | ((t == kept_t) & (o < kept_o)))
        work[NEAR, j] = t if better else kept_t
        best_o[j] = o if better else kept_o
    if any_parallel:
        for j in range(start, start + BLOCK):
            if abs(work[DX, j] * ey - work[DY, j] * ex) <= parallel:
                _consider(ox, oy, work, j, x1, y1, x2, y2, o, limit, best_o)
    far = -math.inf
    for j in range(start, start + BLOCK):  # apart: a float max above would keep it scalar
        far = larger(far, work[NEAR, j])
    return far


@njit(**INNER)
def _sweep_beams(first: int, last: int, ox: float, oy: float, x1: float, y1: float, x2: float,
                 y2: float, o: int, nearest: float, limit: float, work: np.ndarray,
                 best_o: np.ndarray) -> None:
    """Test the blocks of beams ``first..last`` against one segment, skipping those nearer.

    Whole blocks are tested: a beam outside the span that meets the segment
    is a true hit, so it changes nothing the span's beams would not.
    """
    for b in range(first // BLOCK, last // BLOCK + 1):
        if work[FAR, b] >= nearest:  # else every beam of the block hits nearer already
            work[FAR, b] = _sweep_block(b * BLOCK, ox, oy, x1, y1, x2, y2, o, limit, work,
                                        best_o)


# a pinned robot's plan of one wall or robot it lists (``SightLists.plan``): its distance
# bound, the angle its span starts at, the span, and 1.0 when every beam tests it (a wall)
# or the sensor is inside it (a robot), else 0.0
PLAN = 4
DISTANCE, LOW, SPAN, EVERY = 0, 1, 2, 3


@njit(**INNER)
def _span_of(ax: float, ay: float, bx: float, by: float) -> tuple[bool, float, float]:
    """The beams a segment from ``(ax, ay)`` to ``(bx, by)`` (relative to the sensor) may
    meet: every beam (True) when the sensor sits on its line (a span near 0 or pi), else
    its span, counterclockwise from the angle returned with it."""
    # the span runs counterclockwise from ``low``: its orientation is the sign of cross
    cross = ax * by - ay * bx
    lengths2 = (ax * ax + ay * ay) * (bx * bx + by * by)
    if cross * cross <= ANGLE_EPS * ANGLE_EPS * lengths2:
        return True, 0.0, 0.0
    low, high = fast_atan2(ay, ax), fast_atan2(by, bx)
    if cross < 0.0:
        low, high = high, low
    span = high - low
    if span < 0.0:
        span += TAU  # a near-zero span that rounding turned round covers all: still exact
    return False, low, span


@njit(**INNER)
def wall_plan(ox: float, oy: float, x1: float, y1: float, x2: float, y2: float,
              row: np.ndarray) -> None:
    """Fill ``row`` (``PLAN`` entries) with what a scan from ``(ox, oy)`` needs of the wall
    ``(x1, y1, x2, y2)`` whatever the heading: the same numbers as the scan's own."""
    every, low, span = _span_of(x1 - ox, y1 - oy, x2 - ox, y2 - oy)
    row[DISTANCE] = _below(point_segment_distance(ox, oy, x1, y1, x2, y2))
    row[LOW], row[SPAN], row[EVERY] = low, span, 1.0 if every else 0.0


# numpy error model: the inlined block test divides in every lane, without zero checks
@njit(**INNER, error_model="numpy")
def _sweep_segment(ox: float, oy: float, x1: float, y1: float, x2: float, y2: float, o: int,
                   nearest: float, limit: float, layout: Layout, work: np.ndarray,
                   best_o: np.ndarray) -> None:
    """Test one segment against the beams its angular span covers (all beams if unsure).

    ``layout`` is ``(base angle, spacing, count, margin, 1 / spacing)`` of evenly spaced
    beams, or has spacing 0 for beams in no usable order. ``nearest`` is the
    segment's distance from the sensor: beams that already hit nearer skip it.
    """
    every, low, span = _span_of(x1 - ox, y1 - oy, x2 - ox, y2 - oy)
    _sweep_span(every, low, span, ox, oy, x1, y1, x2, y2, o, nearest, limit, layout, work,
                best_o)


@njit(**INNER, error_model="numpy")
def _sweep_kept_span(every: bool, low: float, span: float, ox: float, oy: float, x1: float,
                     y1: float, x2: float, y2: float, o: int, nearest: float, limit: float,
                     layout: Layout, work: np.ndarray, best_o: np.ndarray) -> None:
    """:func:`_sweep_segment` of a wall whose span a pinned robot's plan keeps."""
    _sweep_span(every, low, span, ox, oy, x1, y1, x2, y2, o, nearest, limit, layout, work,
                best_o)


# inlined into both sweeps above, two entry points of one call each: a call more per
# segment cost the Cave's unpinned scans 15%, and _sweep_segment inlined into the ray
# kernel instead of this cost them 15 to 70% (register pressure in _scan_row)
@njit(**INNER)
def _sweep_span(every: bool, low: float, span: float, ox: float, oy: float, x1: float,
                y1: float, x2: float, y2: float, o: int, nearest: float, limit: float,
                layout: Layout, work: np.ndarray, best_o: np.ndarray) -> None:
    """:func:`_sweep_segment` once the segment's span is known (``_span_of``: computed
    now, or kept in a pinned robot's plan)."""
    if layout[1] <= 0.0 or every:  # no order to use, or the sensor on the segment's line
        # np.int64: a literal 0 would compile _sweep_beams a second time
        _sweep_beams(np.int64(0), work.shape[1] - 1, ox, oy, x1, y1, x2, y2, o, nearest, limit,
                     work, best_o)
        return
    rel = _relative(low, layout)
    back, on = _turns(rel, span, layout)  # the span may wrap around past the first beam
    for k in range(1 + back + on):
        first, last = _beam_range(rel + _turn(k, back), span, layout)
        if first <= last:
            _sweep_beams(first, last, ox, oy, x1, y1, x2, y2, o, nearest, limit, work, best_o)


@njit(**INNER)
def _robot_span(cx: float, cy: float, radius: float) -> tuple[bool, float, float]:
    """The beams a robot whose circle (``radius``) is centred at ``(cx, cy)`` from the
    sensor may meet: True when the sensor is inside its circle (each side is swept on
    its own), else the span of the circle, counterclockwise from the angle returned."""
    distance = math.sqrt(cx * cx + cy * cy)
    if distance <= radius * (1.0 + 1e-9):
        return True, 0.0, 0.0
    x = radius / distance  # below 1 here
    half = x / math.sqrt(1.0 - x * x) * (1.0 + 1e-9) + 1e-12  # asin(x) <= tan(asin(x))
    return False, fast_atan2(cy, cx) - half, 2.0 * half


@njit(**INNER)
def robot_plan(cx: float, cy: float, radius: float, row: np.ndarray) -> None:
    """Fill ``row`` (``PLAN`` entries) with what a scan needs of a robot seen at ``(cx,
    cy)`` from the sensor whatever the headings: its distance bound (as the scan's own),
    the span of its circle, and 1.0 when the sensor is inside it (else 0.0)."""
    inside, start, width = _robot_span(cx, cy, radius)
    row[DISTANCE] = larger(_below(math.sqrt(cx * cx + cy * cy) - radius), 0.0)
    row[LOW], row[SPAN], row[EVERY] = start, width, 1.0 if inside else 0.0


# inlined: called for every robot in view, its call would cost more than a hidden check
@njit(**INNER)
def _sweep_robot(ox: float, oy: float, corners: np.ndarray, centers: np.ndarray, r: int,
                 gap: float, radius: float, limit: float, layout: Layout, work: np.ndarray,
                 best_o: np.ndarray) -> None:
    """Test robot ``r``'s edges that face the sensor against the beams its circle spans.

    ``corners`` and ``centers`` are all robots' (a ``RobotIndex``'s: whole arrays,
    as views of one robot's rows would cost reference counting); ``gap`` is a
    lower bound of the robot's distance (from its circle).
    """
    inside, start, width = _robot_span(centers[r, 0] - ox, centers[r, 1] - oy, radius)
    _sweep_robot_span(inside, start, width, ox, oy, corners, r, gap, limit, layout, work,
                      best_o)


@njit(**INNER)
def _sweep_robot_span(inside: bool, start: float, width: float, ox: float, oy: float,
                      corners: np.ndarray, r: int, gap: float, limit: float, layout: Layout,
                      work: np.ndarray, best_o: np.ndarray) -> None:
    """:func:`_sweep_robot` once the robot's span is known (``_robot_span``: computed now,
    or kept in a pinned robot's plan)."""
    if layout[1] <= 0.0 or inside:  # no order, or inside its circle: side by side
        for e in range(4):
            _sweep_segment(ox, oy, corners[r, e, 0], corners[r, e, 1], corners[r, e + 1, 0],
                           corners[r, e + 1, 1], r, gap, limit, layout, work, best_o)
        return
    # the beams its bounding circle spans hold every beam that can meet it: those not
    # yet hit nearer are tested against the sides at once (no span per side); a robot
    # whose circle is hidden that way costs only the blocks' checks
    rel = _relative(start, layout)
    back, on = _turns(rel, width, layout)
    facing = -1  # bit e: side e faces the sensor (found once a block needs it)
    for k in range(1 + back + on):
        first, last = _beam_range(rel + _turn(k, back), width, layout)
        if first > last:
            continue
        for b in range(first // BLOCK, last // BLOCK + 1):
            if work[FAR, b] < gap:
                continue
            if facing < 0:
                facing = _facing_sides(ox, oy, corners, r)
            for e in range(4):
                if facing & (1 << e):
                    work[FAR, b] = _sweep_block(
                        b * BLOCK, ox, oy, corners[r, e, 0], corners[r, e, 1],
                        corners[r, e + 1, 0], corners[r, e + 1, 1], r, limit, work, best_o)


@njit(**INNER)
def _facing_sides(ox: float, oy: float, corners: np.ndarray, r: int) -> int:
    """Bit ``e`` set: robot ``r``'s side ``e`` faces the sensor (or nearly: on its line).

    From outside, a beam meets a convex body first on a side facing the
    sensor, so the others are skipped (a ray through a shared corner still
    meets the facing one).
    """
    facing = 0
    for e in range(4):
        ex, ey = corners[r, e + 1, 0] - corners[r, e, 0], corners[r, e + 1, 1] - corners[r, e, 1]
        wx, wy = ox - corners[r, e, 0], oy - corners[r, e, 1]
        cross = ex * wy - ey * wx  # > 0: the sensor is on the inner (left) side
        if cross <= 1e-9 * (abs(ex) + abs(ey)) * (abs(wx) + abs(wy) + 1.0):
            facing |= 1 << e
    return facing
