"""Exact ray casting of range-finder beams against walls and robot edges.

Per scanning robot, every wall that comes within range of it (listed ahead
of time for its cell, see ``wall_index.py``) and every edge of a robot whose
bounding circle comes within range (``robot_index.py``) is swept once: its
angular span, seen from the sensor, gives the few beams it can hit, and only
those are intersected exactly. The cost per robot is the segments near it
plus the beams each one covers, not the size of the map.

What keeps that cost down:

- walls and robots lying wholly outside the sensor's field of view (behind
  a 180-degree laser, say) are dropped before anything else is computed;
- walls and robots are swept together, nearest first (16 distance rings),
  and beams come in blocks of 4 that remember their farthest hit: a farther
  segment skips every block already hit nearer, and a robot whose bounding
  circle is hidden that way is skipped whole;
- a robot is swept by its sides that face the sensor, each over its own span;
- the 4 beams of a block are tested against a segment without branches.

The order of the sweep changes no result: a hit replaces another only when
nearer, or as near with a lower owner. Beyond the walls' sweep reach (maps
too big for the near lists), beams walk the fine walls grid cell by cell
(Amanatides-Woo) until their first hit. Scanning robots run in parallel
(``prange``); each row is computed from its own inputs only, so the results
are the same bit for bit whatever the number of threads.

The geometry (see :func:`ray_segment_distance`):

- a beam hits a segment where they cross, at distance ``t >= 0`` (an origin
  on a segment gives 0); a hit exactly at the maximum range counts;
- a segment collinear with the beam (within ``COLLINEAR_EPS`` m, at an angle
  below ``PARALLEL_EPS`` rad) is hit at its nearer end;
- the nearest hit wins; at equal distance the lower owner wins (a wall, -1,
  before any robot, and robot 2 before robot 5).

>>> import numpy as np
>>> from mimics.engine.wall_index import build_wall_index
>>> walls = build_wall_index(np.array([[3.0, -1.0, 3.0, 1.0]]), (-5, -5, 5, 5), reach=8.0)
>>> query = RangerQuery(np.zeros((1, 2)), np.zeros(1), np.array([[0.0, np.pi]]),
...                     np.array([8.0]), np.array([-1]))
>>> ranges, owner = cast_rays(query, walls)
>>> ranges.tolist(), owner.tolist()
([[3.0, 8.0]], [[-1, -2]])
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import NamedTuple

import numpy as np
from numba import get_num_threads, njit, parallel_chunksize, prange

from mimics.engine.robot_index import RobotIndex, coerce_robot_index
from mimics.engine.spatial_index import SegmentGrid, cell_span, clip_to_slab, coerce_array
from mimics.engine.wall_index import (
    WallIndex,
    coerce_wall_index,
    near_cell_of,
    point_segment_distance,
)

NO_HIT = -2  # hit_owner of a beam that hit nothing within range
WALL = -1  # hit_owner of a beam that hit a wall
PARALLEL_EPS = 1e-12  # |sin| of the beam-segment angle below which they are parallel
COLLINEAR_EPS = 1e-10  # a parallel segment this close to the beam's line lies on it (m)
ANGLE_EPS = 1e-9  # sin of the angle a segment spans below which all beams test it
ANGLE_SLACK = 2e-4  # rad added around every swept span: 17x fast_atan2's error (< 1.15e-5)
MIN_SPACING = 1e-9  # rad: beams closer than this are tested one by one
TAU = 2.0 * math.pi
RINGS = 16  # distance classes in which walls and robots are swept, nearest first
# robots per work item of the parallel loop, taken in turn: 2.0x on 2 threads (halves: 1.75x)
CHUNK_ROBOTS = 10
# beams per block whose farthest hit so far lets a segment skip them all; on the Cave,
# blocks of 2, 8 and 16 are 7%, 9% and 25% slower
BLOCK = 4
# rows of a scan's work array (one array: every array an inlined helper takes is
# reference-counted at each call); FAR holds one entry per block of beams
DX, DY, NEAR, FAR = 0, 1, 2, 3
# rows of a scan's list array: the robots listed, each item's ring, the order of the sweep
SEEN, RING, ORDER = 0, 1, 2
FAN_COLUMNS = 10  # a row of ``beam_fans``


#: ``(base angle, spacing, count, margin, 1 / spacing)`` of evenly spaced beams (``_layout``)
Layout = tuple[float, float, float, float, float]
#: ``(e0x, e0y, e1x, e1y, kind)``: the beams' field of view (``_field_of_view``)
Cone = tuple[float, float, float, float, float]


class RangerQuery(NamedTuple):
    """The beams of ``k`` scanning robots.

    Attributes:
        origins: ``(k, 2)`` beam origins (robot centres).
        headings: ``(k,)`` headings (rad); a beam's angle is heading + offset.
        offsets: ``(k, B)`` beam angles relative to the heading; NaN marks an
            unused slot (robots of types with fewer beams).
        max_range: ``(k,)`` ranges (m).
        robot: ``(k,)`` int64 index of each scanning robot, whose own edges
            are skipped (-1 for a sensor that is not a robot).
        offset_units: ``(k, B, 2)`` cosines and sines of ``offsets``, or None to
            have them computed (a simulation keeps them per robot type: beam
            directions are then a rotation, not a sine and cosine per beam).
        fans: ``(k, FAN_COLUMNS)`` each row's fan relative to its heading (see
            :func:`beam_fans`), or None to have them computed.

    A beam's direction is ``(cos h, sin h)`` rotated by its offset's unit vector:
    ``(cos h cos o - sin h sin o, sin h cos o + cos h sin o)``.
    """

    origins: np.ndarray
    headings: np.ndarray
    offsets: np.ndarray
    max_range: np.ndarray
    robot: np.ndarray
    offset_units: np.ndarray | None = None
    fans: np.ndarray | None = None


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
    near, far = min(tp, tq), max(tp, tq)
    if far < 0:
        return math.inf
    return max(near, 0.0)


@njit(cache=True, inline="always")
def _cell_exit(grid_start: float, index: int, cell: float, origin: float,
               delta: float) -> float:
    """Ray parameter where it leaves cell ``index`` of one grid axis (inf if parallel)."""
    if delta > 0:
        return (grid_start + (index + 1) * cell - origin) / delta
    if delta < 0:
        return (grid_start + index * cell - origin) / delta
    return math.inf


@njit(cache=True)
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
    ix = int(min(max(math.floor((ox + t0 * dx - gx) / c), 0.0), nx - 1.0))
    iy = int(min(max(math.floor((oy + t0 * dy - gy) / c), 0.0), ny - 1.0))
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
        t_exit = min(tx, ty)
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


@njit(cache=True, inline="always")
def _consider(ox: float, oy: float, work: np.ndarray, j: int, x1: float, y1: float,
              x2: float, y2: float, o: int, limit: float, best_o: np.ndarray) -> None:
    """Let segment ``(x1, y1, x2, y2)`` of owner ``o`` improve beam ``j``'s hit."""
    t = ray_segment_distance(ox, oy, work[DX, j], work[DY, j], x1, y1, x2, y2)
    if t <= limit and (t < work[NEAR, j] or (t == work[NEAR, j] and o < best_o[j])):
        work[NEAR, j] = t
        best_o[j] = o


@njit(cache=True, inline="always")
def _below(distance: float) -> float:
    """A distance shrunk past rounding: beams hitting nearer than it surely skip a segment."""
    return distance - 1e-9 * (1.0 + distance)


@njit(cache=True, inline="always")
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
        far = max(far, work[NEAR, j])
    return far


@njit(cache=True, inline="always")
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


@njit(cache=True, inline="always")
def fast_atan2(y: float, x: float) -> float:
    """``atan2(y, x)`` within 1.15e-5 rad, much faster than libm's.

    Only used to pick which beams a segment may hit (with ``ANGLE_SLACK`` to
    spare, a fraction of a beam: the margin of a degree-spaced fan is the same
    two beams as with an exact arctangent); the hits themselves are computed
    exactly.
    """
    ax, ay = abs(x), abs(y)
    big = max(ax, ay)
    if big == 0.0:
        return 0.0
    a = min(ax, ay) / big
    s = a * a
    # atan on [0, 1], Abramowitz & Stegun 4.4.47 (error below 1.15e-5): a short chain of
    # dependent multiply-adds, two per swept segment
    r = a * (0.9998660 + s * (-0.3302995 + s * (0.1801410 + s * (-0.0851330 + s * 0.0208351))))
    if ay > ax:
        r = 0.5 * math.pi - r
    if x < 0.0:
        r = math.pi - r
    return -r if y < 0.0 else r


@njit(cache=True, inline="always")
def _relative(angle: float, layout: Layout) -> float:
    """``angle`` less the first beam's, in ``[0, 2 pi)`` (up to rounding)."""
    rel = angle - layout[0]
    return rel - TAU * math.floor(rel * (1.0 / TAU))


@njit(cache=True, inline="always")
def _beam_range(rel: float, span: float, layout: Layout) -> tuple[int, int]:
    """Beams whose angle less the first beam's lies in ``[rel, rel + span]``, with margin.

    Empty (first > last) when no beam is there; spans wholly before the first
    beam or after the last are told apart before any rounding to beams.
    """
    _, spacing, count, margin, per_rad = layout
    if rel + span < -(margin + 1.0) * spacing or rel > (count + margin) * spacing:
        return 1, 0
    # products by the reciprocal differ from quotients by rounding only: the margin covers it
    first = max(math.ceil(rel * per_rad) - int(margin), 0)
    last = min(math.floor((rel + span) * per_rad) + int(margin), int(count) - 1)
    return first, last


@njit(cache=True, inline="always")
def _turns(rel: float, span: float, layout: Layout) -> tuple[bool, bool]:
    """Whether ``[rel, rel + span]`` may also overlap the beams one turn back, one turn on.

    ``rel`` is in ``[0, 2 pi)`` (``_relative``): the span seen one turn back
    reaches the first beams when it crosses a full turn, one turn on only in
    fans of about a full turn. Most spans need neither.
    """
    _, spacing, count, margin, _ = layout
    return (rel + span - TAU >= -(margin + 1.0) * spacing,
            rel + TAU <= (count + margin) * spacing)


@njit(cache=True, inline="always")
def _turn(k: int, back: bool) -> float:
    """The ``k``-th shift to try: 0, then -2 pi if ``back``, then +2 pi."""
    return 0.0 if k == 0 else (-TAU if back and k == 1 else TAU)


# numpy error model: the inlined block test divides in every lane, without zero checks
@njit(cache=True, error_model="numpy")
def _sweep_segment(ox: float, oy: float, x1: float, y1: float, x2: float, y2: float, o: int,
                   nearest: float, limit: float, layout: Layout, work: np.ndarray,
                   best_o: np.ndarray) -> None:
    """Test one segment against the beams its angular span covers (all beams if unsure).

    ``layout`` is ``(base angle, spacing, count, margin, 1 / spacing)`` of evenly spaced
    beams, or has spacing 0 for beams in no usable order. ``nearest`` is the
    segment's distance from the sensor: beams that already hit nearer skip it.
    """
    ax, ay, bx, by = x1 - ox, y1 - oy, x2 - ox, y2 - oy
    cross = ax * by - ay * bx
    lengths2 = (ax * ax + ay * ay) * (bx * bx + by * by)
    if layout[1] <= 0.0 or cross * cross <= ANGLE_EPS * ANGLE_EPS * lengths2:
        # no order to use, or the sensor sits on the segment's line (span near 0 or pi)
        _sweep_beams(0, work.shape[1] - 1, ox, oy, x1, y1, x2, y2, o, nearest, limit, work,
                     best_o)
        return
    # the span runs counterclockwise from ``low``: its orientation is the sign of cross
    low, high = fast_atan2(ay, ax), fast_atan2(by, bx)
    if cross < 0.0:
        low, high = high, low
    span = high - low
    if span < 0.0:
        span += TAU  # a near-zero span that rounding turned round covers all: still exact
    rel = _relative(low, layout)
    back, on = _turns(rel, span, layout)  # the span may wrap around past the first beam
    for k in range(1 + back + on):
        first, last = _beam_range(rel + _turn(k, back), span, layout)
        if first <= last:
            _sweep_beams(first, last, ox, oy, x1, y1, x2, y2, o, nearest, limit, work, best_o)


# inlined: called for every robot in view, its call would cost more than a hidden check
@njit(cache=True, inline="always")
def _sweep_robot(ox: float, oy: float, corners: np.ndarray, centers: np.ndarray, r: int,
                 gap: float, radius: float, limit: float, layout: Layout, work: np.ndarray,
                 best_o: np.ndarray) -> None:
    """Test robot ``r``'s edges that face the sensor against the beams its circle spans.

    ``corners`` and ``centers`` are all robots' (a ``RobotIndex``'s: whole arrays,
    as views of one robot's rows would cost reference counting); ``gap`` is a
    lower bound of the robot's distance (from its circle).
    """
    cx, cy = centers[r, 0] - ox, centers[r, 1] - oy
    distance = math.sqrt(cx * cx + cy * cy)
    if layout[1] <= 0.0 or distance <= radius * (1.0 + 1e-9):  # no order, or inside its circle
        for e in range(4):
            _sweep_segment(ox, oy, corners[r, e, 0], corners[r, e, 1], corners[r, e + 1, 0],
                           corners[r, e + 1, 1], r, gap, limit, layout, work, best_o)
        return
    # the beams its bounding circle spans hold every beam that can meet it: those not
    # yet hit nearer are tested against the sides at once (no span per side); a robot
    # whose circle is hidden that way costs only the blocks' checks
    x = radius / distance  # below 1 here
    half = x / math.sqrt(1.0 - x * x) * (1.0 + 1e-9) + 1e-12  # asin(x) <= tan(asin(x))
    rel = _relative(fast_atan2(cy, cx) - half, layout)
    back, on = _turns(rel, 2.0 * half, layout)
    facing = -1  # bit e: side e faces the sensor (found once a block needs it)
    for k in range(1 + back + on):
        first, last = _beam_range(rel + _turn(k, back), 2.0 * half, layout)
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


@njit(cache=True, inline="always")
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


@njit(cache=True)
def _layout(offsets: np.ndarray) -> Layout:
    """``(first offset, spacing, count, margin, 1 / spacing)`` of a row of beams (spacing 0:
    none); a scan adds its heading to the first.

    Rows whose used beams form a prefix of increasing, near-evenly spaced
    angles spanning at most a full turn get their spacing; the margin (in
    beams) covers the deviation from even spacing, ``fast_atan2``'s error and
    rounding.
    """
    beams = offsets.shape[0]
    unordered = (offsets[0], 0.0, float(beams), 0.0, 0.0)
    count = 0
    while count < beams and not math.isnan(offsets[count]):
        count += 1
    if count < 2 or count * 2 < beams:  # few beams: one by one costs as little
        return unordered
    for j in range(count, beams):
        if not math.isnan(offsets[j]):
            return unordered  # used beams are not a prefix
    spacing = (offsets[count - 1] - offsets[0]) / (count - 1)
    if not (spacing > MIN_SPACING and spacing * (count - 1) <= TAU):
        return unordered
    deviation = 0.0
    for j in range(count):
        deviation = max(deviation, abs(offsets[j] - (offsets[0] + j * spacing)))
    margin = 1.0 + math.ceil((deviation + ANGLE_SLACK) / spacing)
    if margin > 3.0:
        return unordered
    return (offsets[0], spacing, float(count), margin, 1.0 / spacing)


@njit(cache=True)
def _field_of_view(offsets: np.ndarray) -> Cone:
    """``(e0x, e0y, e1x, e1y, kind)``: the cone swept counterclockwise from ``e0`` to ``e1``.

    The edges point along the lowest and highest beam offsets (a scan rotates
    them to its heading like its beams, so every beam lies between them up to
    rounding, which the cull's slack covers); ``kind`` is 1
    for a cone narrower than a half turn (outside it: beyond either edge), 2
    for a wider one (outside it: beyond both) and 0 when there is no cone to
    cull by (beams in no order, or a near-full turn).
    """
    low, high, count = math.inf, -math.inf, 0
    for j in range(offsets.shape[0]):
        if not math.isnan(offsets[j]):
            low, high, count = min(low, offsets[j]), max(high, offsets[j]), count + 1
    width = high - low
    if count == 0 or width >= TAU - 1e-6:
        return (1.0, 0.0, 1.0, 0.0, 0.0)
    return (math.cos(low), math.sin(low), math.cos(high), math.sin(high),
            1.0 if width < math.pi - 1e-6 else 2.0)


@njit(cache=True, inline="always")
def _beyond_edges(px: float, py: float, clearance: float, cone: Cone) -> int:
    """Bits 0 and 1: ``p`` lies more than ``clearance`` beyond edge 0, 1.

    The slack covers rounding and the collinear tolerance of the hit test.
    """
    slack = clearance + 2.0 * COLLINEAR_EPS + 1e-9 * (abs(px) + abs(py))
    bits = 0
    if cone[0] * py - cone[1] * px < -slack:
        bits |= 1
    if cone[2] * py - cone[3] * px > slack:
        bits |= 2
    return bits


@njit(cache=True, inline="always")
def _outside_view(a: int, b: int, kind: float) -> bool:
    """Whether a convex set whose extreme points have edge bits ``a`` and ``b`` is unseen."""
    common = a & b
    return common != 0 if kind == 1.0 else (kind == 2.0 and common == 3)


@njit(cache=True)
def _by_distance(distance: np.ndarray, count: int, limit: float, lists: np.ndarray) -> int:
    """Put the indices of ``distance[:count]`` within ``limit`` in ``lists[ORDER]``, roughly
    nearest first; returns how many there are.

    A counting sort into ``RINGS`` rings: O(n), where a full sort of a few
    hundred walls per robot would cost more than sweeping them. ``lists`` is the
    scan's scratch space (its ``RING`` row is overwritten too).
    """
    counts = np.zeros(RINGS + 1, dtype=np.int64)
    for p in range(count):
        d = distance[p]
        ring = -1 if d > limit else (0 if d <= 0.0 else min(int(d / limit * RINGS), RINGS - 1))
        lists[RING, p] = ring
        if ring >= 0:
            counts[ring + 1] += 1
    for k in range(RINGS):
        counts[k + 1] += counts[k]
    kept = counts[RINGS]
    for p in range(count):
        ring = lists[RING, p]
        if ring >= 0:
            lists[ORDER, counts[ring]] = p
            counts[ring] += 1
    return kept


# numpy error model: the inlined block test of robots' sides divides in every lane
@njit(cache=True, error_model="numpy")
def _scan_row(query: RangerQuery, i: int, grid: SegmentGrid,
              near: SegmentGrid, reach: float, robots: RobotIndex, ranges: np.ndarray,
              owners: np.ndarray, work: np.ndarray, best_o: np.ndarray, distance: np.ndarray,
              lists: np.ndarray) -> None:
    """Fill one scanning robot's ``ranges`` and hit ``owners``.

    The walls come as the fields of a ``WallIndex`` (``grid``, ``near``,
    ``reach``): parallel kernels take no nested tuples. ``work`` and ``best_o``
    are scratch space of whole blocks of beams, ``distance`` and ``lists`` of the
    walls and robots listed (``_list_capacity``), reused from one robot to the next.
    """
    beams = query.offsets.shape[1]
    segs = near.segments
    ox, oy = query.origins[i, 0], query.origins[i, 1]
    limit = query.max_range[i]
    me = query.robot[i]
    heading = query.headings[i]
    fan = query.fans[i]
    layout = (heading + fan[0], fan[1], fan[2], fan[3], fan[4])
    ch, sh = math.cos(heading), math.sin(heading)  # the rotation to the heading
    # whole blocks of beams; the padding's NaN directions never hit, -inf: never tested
    units = query.offset_units
    for j in range(best_o.shape[0]):
        work[FAR, j] = math.inf  # (one entry per block is used)
        best_o[j] = NO_HIT
        if j < beams and not math.isnan(query.offsets[i, j]):
            co, so = units[i, j, 0], units[i, j, 1]
            work[DX, j], work[DY, j] = ch * co - sh * so, sh * co + ch * so
            work[NEAR, j] = math.inf
        else:
            work[DX, j], work[DY, j], work[NEAR, j] = math.nan, math.nan, -math.inf
    # the field of view's edges rotated like the beams: every beam lies between them
    cone = (ch * fan[5] - sh * fan[6], sh * fan[5] + ch * fan[6],
            ch * fan[7] - sh * fan[8], sh * fan[7] + ch * fan[8], fan[9])
    # the walls listed for the sensor's cell (none outside the near grid)
    cell = near_cell_of(near, ox, oy)
    certain = reach if cell >= 0 else 0.0
    listed = near.cell_items[0:0]
    if cell >= 0:
        listed = near.cell_items[near.cell_start[cell]: near.cell_start[cell + 1]]
    walls = listed.shape[0]
    # the robots whose bounding circle comes within range
    span = limit + robots.max_radius
    nx = robots.shape[0]
    ix0, ix1 = cell_span(ox - span, ox + span, robots.origin[0], robots.cell, nx)
    iy0, iy1 = cell_span(oy - span, oy + span, robots.origin[1], robots.cell, robots.shape[1])
    # a lower bound of each one's distance; inf for those no beam can reach
    for p in range(walls):
        s = listed[p]
        x1, y1, x2, y2 = segs[s, 0], segs[s, 1], segs[s, 2], segs[s, 3]
        if _outside_view(_beyond_edges(x1 - ox, y1 - oy, 0.0, cone),
                         _beyond_edges(x2 - ox, y2 - oy, 0.0, cone), cone[4]):
            distance[p] = math.inf
        else:
            distance[p] = _below(point_segment_distance(ox, oy, x1, y1, x2, y2))
    found = 0
    corners, centers, radius = robots.corners, robots.centers, robots.radius
    grid_start, grid_items = robots.grid_start, robots.grid_items
    for iy in range(iy0, iy1 + 1):  # the cells of a row are contiguous in the CSR
        for p in range(grid_start[iy * nx + ix0], grid_start[iy * nx + ix1 + 1]):
            r = grid_items[p]
            lists[SEEN, found] = r
            cx, cy = centers[r, 0] - ox, centers[r, 1] - oy
            bits = _beyond_edges(cx, cy, radius[r], cone)
            if r == me or _outside_view(bits, bits, cone[4]):
                distance[walls + found] = math.inf
            else:
                distance[walls + found] = max(_below(math.sqrt(cx * cx + cy * cy) - radius[r]),
                                              0.0)
            found += 1
    # walls and robots together, nearest first: farther ones then skip the beams already
    # hit (most beams of a crowded scan end on a neighbour, in front of the walls)
    for q in range(_by_distance(distance, walls + found, limit, lists)):
        p = lists[ORDER, q]
        if p < walls:
            s = listed[p]
            # np.int64: a literal WALL would compile _sweep_segment a second time
            _sweep_segment(ox, oy, segs[s, 0], segs[s, 1], segs[s, 2], segs[s, 3],
                           np.int64(WALL), distance[p], limit, layout, work, best_o)
        else:
            r = lists[SEEN, p - walls]
            _sweep_robot(ox, oy, corners, centers, r, distance[p], radius[r], limit, layout,
                         work, best_o)
    if certain < limit:  # beyond the sweep's reach: walk the fine grid
        for j in range(beams):
            if work[NEAR, j] > certain:
                work[NEAR, j], best_o[j] = _trace(grid, ox, oy, work[DX, j], work[DY, j], limit,
                                                  me, work[NEAR, j], best_o[j], certain)
    for j in range(beams):
        ranges[j] = math.nan if work[NEAR, j] == -math.inf else (
            limit if best_o[j] == NO_HIT else work[NEAR, j])
        owners[j] = best_o[j]


@njit(parallel=True, cache=True)
def _cast_kernel(query: RangerQuery, grid: SegmentGrid,
                 near: SegmentGrid, reach: float, robots: RobotIndex, ranges: np.ndarray,
                 hit_owner: np.ndarray) -> None:
    """Fill ``ranges`` and ``hit_owner`` row by row (one scanning robot per row).

    Work items are chunks of ``CHUNK_ROBOTS`` rows sharing one scratch space.
    """
    k, beams = query.offsets.shape
    padded = (beams + BLOCK - 1) // BLOCK * BLOCK
    capacity = _list_capacity(near, robots)
    for chunk in prange((k + CHUNK_ROBOTS - 1) // CHUNK_ROBOTS):
        work = np.empty((4, padded))
        best_o = np.empty(padded, dtype=np.int64)
        distance = np.empty(capacity)
        lists = np.empty((3, capacity), dtype=np.int64)
        for i in range(chunk * CHUNK_ROBOTS, min(k, (chunk + 1) * CHUNK_ROBOTS)):
            _scan_row(query, i, grid, near, reach, robots, ranges[i], hit_owner[i], work, best_o,
                      distance, lists)


@njit(cache=True)
def _list_capacity(near: SegmentGrid, robots: RobotIndex) -> int:
    """The most walls and robots a scan can list: the longest near list and every robot."""
    most = 0
    for c in range(near.cell_start.shape[0] - 1):
        most = max(most, near.cell_start[c + 1] - near.cell_start[c])
    return most + robots.grid_items.shape[0]


def _as_query(query: RangerQuery) -> RangerQuery:
    offsets = coerce_array(query.offsets, np.float64, 2, "offsets")
    k = offsets.shape[0]
    units = None if query.offset_units is None else coerce_array(
        query.offset_units, np.float64, 3, "offset_units")
    fans = None if query.fans is None else coerce_array(query.fans, np.float64, 2, "fans")
    q = RangerQuery(coerce_array(query.origins, np.float64, 2, "origins"),
                    coerce_array(query.headings, np.float64, 1, "headings"), offsets,
                    coerce_array(query.max_range, np.float64, 1, "max_range"),
                    coerce_array(query.robot, np.int64, 1, "robot"), units, fans)
    if q.origins.shape != (k, 2) or any(len(a) != k for a in (q.headings, q.max_range, q.robot)):
        raise ValueError(f"query arrays disagree on the number of scanning robots ({k})")
    if units is not None and units.shape != (*offsets.shape, 2):
        raise ValueError(f"offset_units must have shape {(*offsets.shape, 2)}, got {units.shape}")
    if fans is not None and fans.shape != (k, FAN_COLUMNS):
        raise ValueError(f"fans must have shape {(k, FAN_COLUMNS)}, got {fans.shape}")
    if not (np.all(np.isfinite(q.origins)) and np.all(np.isfinite(q.headings))):
        raise ValueError("beam origins and headings must be finite")
    if np.isinf(q.offsets).any():
        raise ValueError("beam offsets must be finite (or NaN for an unused slot)")
    if not np.all(q.max_range >= 0):
        raise ValueError("max_range must be >= 0")
    return q


def cast_rays(query: RangerQuery, walls: WallIndex,
              robots: RobotIndex | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Trace every beam to its nearest wall or other robot's edge.

    Args:
        query: the beams (see :class:`RangerQuery`).
        walls: the map's walls (``build_wall_index``).
        robots: the robots that can be seen (``build_robot_index``), or None.

    Returns:
        ``ranges (k, B)``: distance to the nearest hit, ``max_range`` when
        nothing is hit within range, NaN in unused slots; ``hit_owner (k, B)``
        int64: -2 no hit (or unused slot), -1 a wall, ``j >= 0`` robot ``j``.

    Raises:
        ValueError: mismatched shapes, non-finite origins, headings or
            offsets, or a negative (or NaN) range.
    """
    return trace_beams(_as_query(query), coerce_wall_index(walls), coerce_robot_index(robots))


def trace_beams(query: RangerQuery, walls: WallIndex, robots: RobotIndex,
                out: tuple[np.ndarray, np.ndarray] | None = None
                ) -> tuple[np.ndarray, np.ndarray]:
    """:func:`cast_rays` without the checks, for the engine's own arrays.

    The query's arrays must be C-contiguous, of the dtypes and shapes
    :class:`RangerQuery` gives, with finite origins and headings. ``out``:
    C-contiguous ``(k, B)`` float64 and int64 arrays to fill (and return)
    instead of new ones.
    """
    k, beams = query.offsets.shape
    if query.offset_units is None:
        query = query._replace(offset_units=offset_units(query.offsets))
    if query.fans is None:
        query = query._replace(fans=beam_fans(query.offsets))
    if out is None:
        out = (np.empty((k, beams)), np.empty((k, beams), dtype=np.int64))
    ranges, hit_owner = out
    if k and beams:
        if k <= CHUNK_ROBOTS or get_num_threads() == 1:
            # one work item, or one thread: the chunk size changes nothing (and the
            # context costs about as much as scanning one robot)
            _cast_kernel(query, walls.grid, walls.near, walls.reach, robots, ranges, hit_owner)
        else:
            # small chunks, taken in turn: robots' costs differ, equal halves would idle a
            # thread
            with parallel_chunksize(1):
                _cast_kernel(query, walls.grid, walls.near, walls.reach, robots, ranges,
                             hit_owner)
    return ranges, hit_owner


def offset_units(offsets: np.ndarray) -> np.ndarray:
    """``(..., 2)``: the cosine and sine of each beam offset (NaN for unused slots)."""
    return np.ascontiguousarray(np.stack([np.cos(offsets), np.sin(offsets)], axis=-1))


@njit(cache=True)
def beam_fans(offsets: np.ndarray) -> np.ndarray:
    """``(k, FAN_COLUMNS)``: each row of beam offsets' fan, relative to its heading.

    Columns 0-4 are its ``_layout`` (the first offset, spacing, count, margin,
    1 / spacing), 5-9 its ``_field_of_view`` (the unit vectors of the lowest
    and highest offsets, and the cone's kind). A scan adds its heading to the
    first and rotates the second: rows repeat per robot type, so a simulation
    computes them once.
    """
    fans = np.zeros((offsets.shape[0], FAN_COLUMNS))
    if offsets.shape[1] == 0:
        return fans  # no beams: no scan will read a fan
    for i in range(offsets.shape[0]):
        layout, cone = _layout(offsets[i]), _field_of_view(offsets[i])
        for c in range(5):
            fans[i, c], fans[i, 5 + c] = layout[c], cone[c]
    return fans


def kernels_cached() -> bool:
    """False when Numba's on-disk cache lacks the ray kernel: the first run compiles it.

    Looks in the folder Numba itself caches this module's kernels in (beside
    this file, or under ``NUMBA_CACHE_DIR`` when set).
    """
    return any(_cache_folder().glob("ranger._cast_kernel-*.nbi"))


def _cache_folder() -> Path:
    """Where Numba caches this module's kernels (its own locator's choice)."""
    return Path(_cast_kernel._cache._cache_path)
