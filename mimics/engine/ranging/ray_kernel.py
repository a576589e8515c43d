"""The ray kernel: each scanning robot's row of ranges and hit owners, computed from
its own inputs only, in chunks of robots that the calling thread and helper threads
take in turn (``kernel_threads.py``, ``kernel_chunks.py``). The entry points, the
geometry's rules and the threads' hand-out are in ``ranger.py``; the sweep of one
wall or robot over the beams it spans is in ``beam_sweep.py``, which beams a span
covers in ``beam_fan.py``.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.compiling.kernel_options import INNER
from mimics.engine.helper_threads.chunks import begin, chunk_done, end, take
from mimics.engine.ranging.beam_fan import _beyond_edges, _outside_view
from mimics.engine.ranging.beam_sweep import (
    BLOCK,
    DISTANCE,
    DX,
    DY,
    EVERY,
    FAR,
    LOW,
    NEAR,
    NO_HIT,
    SPAN,
    WALL,
    _below,
    _sweep_kept_span,
    _sweep_robot,
    _sweep_robot_span,
    _sweep_segment,
    _trace,
)
from mimics.engine.ranging.point_cull import SightLists
from mimics.engine.ranging.wall_index import near_cell_of, point_segment_distance
from mimics.engine.robot_index import RobotIndex, robots_near
from mimics.engine.spatial_index import SegmentGrid

RINGS = 16  # distance classes in which walls and robots are swept, nearest first
# robots per chunk, the unit the threads take in turn (4 measured the same as 10)
CHUNK_ROBOTS = 10


# rows of a scan's list array: the robots listed, each item's ring, the order of the sweep
SEEN, RING, ORDER = 0, 1, 2


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


@njit(**INNER)
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
        ring = -1 if d > limit else (0 if d <= 0.0 else smaller(int(d / limit * RINGS), RINGS - 1))
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
@njit(**INNER, error_model="numpy")
def _scan_row(query: RangerQuery, i: int, grid: SegmentGrid,
              near: SegmentGrid, reach: float, robots: RobotIndex, sight: SightLists,
              ranges: np.ndarray, owners: np.ndarray, work: np.ndarray, best_o: np.ndarray,
              distance: np.ndarray, lists: np.ndarray) -> None:
    """Fill one scanning robot's ``ranges`` and hit ``owners``.

    The walls come as the fields of a ``WallIndex`` (``grid``, ``near``,
    ``reach``); a robot pinned in ``sight`` sweeps its own lists instead of its
    cell's walls and the robots in range, with the distances and spans their plans
    keep. ``work`` and ``best_o`` are scratch space of whole blocks of beams,
    ``distance`` and ``lists`` of the walls and robots listed (``_list_capacity``),
    reused from one robot to the next.
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
    pinned = 0 <= me < sight.pinned.shape[0] and sight.pinned[me]
    listed = near.cell_items[0:0]
    planned = False  # its walls' distances and spans kept with its lists
    first = 0
    if pinned:  # (a pinned robot's cell is in the grid)
        first = sight.spans[me, 0]
        listed = sight.items[first:sight.spans[me, 1]]
        planned = sight.plan.shape[0] >= sight.spans[me, 3]
    elif cell >= 0:
        listed = near.cell_items[near.cell_start[cell]: near.cell_start[cell + 1]]
    walls = listed.shape[0]
    # the robots whose bounding circle comes within range (or those pinned lists keep)
    found = 0
    seen_first = 0  # where a pinned robot's robots and their plans start
    if pinned:
        seen_first = sight.spans[me, 2]
        for p in range(seen_first, sight.spans[me, 3]):
            lists[SEEN, found] = sight.items[p]
            found += 1
    else:
        found = robots_near(robots, ox, oy, limit + robots.max_radius, lists[SEEN])
    # a lower bound of each one's distance; inf for those no beam can reach
    for p in range(walls):
        s = listed[p]
        x1, y1, x2, y2 = segs[s, 0], segs[s, 1], segs[s, 2], segs[s, 3]
        if _outside_view(_beyond_edges(x1 - ox, y1 - oy, 0.0, cone),
                         _beyond_edges(x2 - ox, y2 - oy, 0.0, cone), cone[4]):
            distance[p] = math.inf
        elif planned:
            distance[p] = sight.plan[first + p, DISTANCE]
        else:
            distance[p] = _below(point_segment_distance(ox, oy, x1, y1, x2, y2))
    corners, centers, radius = robots.corners, robots.centers, robots.radius
    for f in range(found):
        r = lists[SEEN, f]
        cx, cy = centers[r, 0] - ox, centers[r, 1] - oy
        bits = _beyond_edges(cx, cy, radius[r], cone)
        if r == me or _outside_view(bits, bits, cone[4]):
            distance[walls + f] = math.inf
        elif planned:
            distance[walls + f] = sight.plan[seen_first + f, DISTANCE]
        else:
            distance[walls + f] = larger(_below(math.sqrt(cx * cx + cy * cy) - radius[r]), 0.0)
    # walls and robots together, nearest first: farther ones then skip the beams already
    # hit (most beams of a crowded scan end on a neighbour, in front of the walls)
    for q in range(_by_distance(distance, walls + found, limit, lists)):
        p = lists[ORDER, q]
        if p < walls and planned:
            s, plan = listed[p], sight.plan[first + p]
            _sweep_kept_span(plan[EVERY] != 0.0, plan[LOW], plan[SPAN], ox, oy, segs[s, 0],
                             segs[s, 1], segs[s, 2], segs[s, 3], np.int64(WALL), distance[p],
                             limit, layout, work, best_o)
        elif p < walls:
            s = listed[p]
            # np.int64: a literal WALL would compile _sweep_segment a second time
            _sweep_segment(ox, oy, segs[s, 0], segs[s, 1], segs[s, 2], segs[s, 3],
                           np.int64(WALL), distance[p], limit, layout, work, best_o)
        elif planned:
            r, plan = lists[SEEN, p - walls], sight.plan[seen_first + p - walls]
            _sweep_robot_span(plan[EVERY] != 0.0, plan[LOW], plan[SPAN], ox, oy, corners, r,
                              distance[p], limit, layout, work, best_o)
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


@njit(cache=True, nogil=True)
def _cast_rows(beams: tuple, wall_grid: tuple, near_lists: tuple, reach: float,
               robot_index: tuple, sight_lists: tuple, ranges: np.ndarray,
               hit_owner: np.ndarray, control: np.ndarray, share: np.ndarray,
               role: int, until: int) -> None:
    """Fill rows of ``ranges`` and ``hit_owner``, a chunk of ``CHUNK_ROBOTS`` rows at a
    time, taking chunks with the helper threads that join (``kernel_threads``: the
    thread's ``role``, and the chunk it waits for).

    A thread's chunks share one scratch space.
    ``beams``, ``wall_grid``, ``near_lists``, ``robot_index`` and ``sight_lists`` are
    the fields of a ``RangerQuery``, two ``SegmentGrid``, a ``RobotIndex`` and
    ``SightLists`` as plain tuples:
    the dispatcher types those in C (see ``collision._collide_kernel``).
    """
    query, grid = RangerQuery(*beams), SegmentGrid(*wall_grid)
    near, robots = SegmentGrid(*near_lists), RobotIndex(*robot_index)
    sight = SightLists(*sight_lists)
    k, beams = query.offsets.shape
    padded = (beams + BLOCK - 1) // BLOCK * BLOCK
    capacity = _list_capacity(near, robots)
    work = np.empty((4, padded))
    best_o = np.empty(padded, dtype=np.int64)
    distance = np.empty(capacity)
    lists = np.empty((3, capacity), dtype=np.int64)
    chunks = (k + CHUNK_ROBOTS - 1) // CHUNK_ROBOTS
    begin(control, share, role)
    chunk = take(share, role, until, chunks)
    while chunk >= 0:
        for i in range(chunk * CHUNK_ROBOTS, smaller(k, (chunk + 1) * CHUNK_ROBOTS)):
            _scan_row(query, i, grid, near, reach, robots, sight, ranges[i], hit_owner[i], work,
                      best_o, distance, lists)
        chunk_done(share, chunk)
        chunk = take(share, role, until, chunks)
    end(share, role, until, chunks)


@njit(**INNER)
def _list_capacity(near: SegmentGrid, robots: RobotIndex) -> int:
    """The most walls and robots a scan can list: the longest near list and every robot."""
    most = 0
    for c in range(near.cell_start.shape[0] - 1):
        most = larger(most, near.cell_start[c + 1] - near.cell_start[c])
    return most + robots.grid_items.shape[0]
