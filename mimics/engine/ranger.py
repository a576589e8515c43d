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
(Amanatides-Woo) until their first hit. Scanning robots run in parallel:
chunks of rows taken in turn by the calling thread and up to Numba's thread
count less one helper threads (``kernel_threads.py``; one thread per
``MIN_BEAMS_PER_PART`` beams at most: a small scan does not pay for a
second core), as the kernel releases the GIL (``nogil``). Not a ``prange``
kernel: its parallel wrapper took a fifth of the first-run compile, and
OpenMP's threads spin for long between steps, which on a busy machine
starves the Python side of the step. Each row is computed from its own
inputs only, so the results are the same bit for bit whatever the number
of threads and whichever thread takes a chunk.

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
from typing import NamedTuple

import numpy as np
from numba import get_num_threads, njit

# "X as X": names callers import from here (the module was one before it was split)
from mimics.engine.beam_fan import ANGLE_SLACK as ANGLE_SLACK
from mimics.engine.beam_fan import (
    FAN_COLUMNS,
    _beyond_edges,
    _outside_view,
    beam_fans,
    offset_units,
)
from mimics.engine.beam_fan import fast_atan2 as fast_atan2
from mimics.engine.beam_sweep import (
    BLOCK,
    DX,
    DY,
    FAR,
    NEAR,
    NO_HIT,
    WALL,
    _below,
    _sweep_robot,
    _sweep_segment,
    _trace,
)
from mimics.engine.beam_sweep import ray_segment_distance as ray_segment_distance
from mimics.engine.kernel_threads import (
    LEAD,
    Flight,
    begin,
    chunk_done,
    end,
    helpers,
    solo_arrays,
    take,
)
from mimics.engine.point_cull import SightLists, no_sight_lists
from mimics.engine.robot_index import RobotIndex, coerce_robot_index, robots_near
from mimics.engine.spatial_index import SegmentGrid, coerce_array
from mimics.engine.wall_index import (
    WallIndex,
    coerce_wall_index,
    near_cell_of,
    point_segment_distance,
)

RINGS = 16  # distance classes in which walls and robots are swept, nearest first
# robots per chunk, the unit the threads take in turn (4 measured the same as 10)
CHUNK_ROBOTS = 10
# beams per thread below which a scan runs on the calling thread alone: a spinning
# helper joins within microseconds, a sleeping one within 40 to 70 us (kernel_threads)
MIN_BEAMS_PER_PART = 256
NO_SIGHT_LISTS = no_sight_lists()  # no robot pinned


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
              near: SegmentGrid, reach: float, robots: RobotIndex, sight: SightLists,
              ranges: np.ndarray, owners: np.ndarray, work: np.ndarray, best_o: np.ndarray,
              distance: np.ndarray, lists: np.ndarray) -> None:
    """Fill one scanning robot's ``ranges`` and hit ``owners``.

    The walls come as the fields of a ``WallIndex`` (``grid``, ``near``,
    ``reach``); a robot pinned in ``sight`` sweeps its own lists instead of its
    cell's walls and the robots in range. ``work`` and ``best_o``
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
    pinned = 0 <= me < sight.pinned.shape[0] and sight.pinned[me]
    listed = near.cell_items[0:0]
    if pinned:  # (a pinned robot's cell is in the grid)
        listed = sight.items[sight.spans[me, 0]:sight.spans[me, 1]]
    elif cell >= 0:
        listed = near.cell_items[near.cell_start[cell]: near.cell_start[cell + 1]]
    walls = listed.shape[0]
    # the robots whose bounding circle comes within range (or those pinned lists keep)
    found = 0
    if pinned:
        for p in range(sight.spans[me, 2], sight.spans[me, 3]):
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
        else:
            distance[p] = _below(point_segment_distance(ox, oy, x1, y1, x2, y2))
    corners, centers, radius = robots.corners, robots.centers, robots.radius
    for f in range(found):
        r = lists[SEEN, f]
        cx, cy = centers[r, 0] - ox, centers[r, 1] - oy
        bits = _beyond_edges(cx, cy, radius[r], cone)
        if r == me or _outside_view(bits, bits, cone[4]):
            distance[walls + f] = math.inf
        else:
            distance[walls + f] = max(_below(math.sqrt(cx * cx + cy * cy) - radius[r]), 0.0)
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
        for i in range(chunk * CHUNK_ROBOTS, min(k, (chunk + 1) * CHUNK_ROBOTS)):
            _scan_row(query, i, grid, near, reach, robots, sight, ranges[i], hit_owner[i], work,
                      best_o, distance, lists)
        chunk_done(share, chunk)
        chunk = take(share, role, until, chunks)
    end(share, role, until, chunks)


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
                out: tuple[np.ndarray, np.ndarray] | None = None,
                sight: SightLists = NO_SIGHT_LISTS) -> tuple[np.ndarray, np.ndarray]:
    """:func:`cast_rays` without the checks, for the engine's own arrays.

    The query's arrays must be C-contiguous, of the dtypes and shapes
    :class:`RangerQuery` gives, with finite origins and headings. ``out``:
    C-contiguous ``(k, B)`` float64 and int64 arrays to fill (and return)
    instead of new ones. ``sight``: the lists of robots that stand still
    (``still_scans.py``), by robot index (``query.robot``).
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
        args = _kernel_args(query, walls, robots, sight, ranges, hit_owner)
        chunks, parts = _chunks_and_parts(k, beams)
        if parts <= 1:
            _cast_rows(*args, *solo_arrays(chunks), LEAD, 0)
        else:
            helpers(parts - 1).run(_cast_rows, args, chunks, parts - 1)
    return ranges, hit_owner


class RowsInFlight:
    """A trace that helper threads go on with (:func:`start_beams`)."""

    def __init__(self, flight: Flight) -> None:
        self._flight = flight

    def row_done(self, row: int) -> bool:
        """Whether ``row`` is traced (a look, no wait)."""
        return self._flight.done(row // CHUNK_ROBOTS)

    def finish(self) -> None:
        """Return once every row is traced; no thread writes them afterwards."""
        self._flight.finish()


def start_beams(query: RangerQuery, walls: WallIndex, robots: RobotIndex,
                out: tuple[np.ndarray, np.ndarray], sight: SightLists,
                first_row: int) -> RowsInFlight | None:
    """:func:`trace_beams` into ``out`` on helper threads, returning once row
    ``first_row`` is traced, so that the caller can read it while the others are
    traced; None, with nothing traced, when the scan is for one thread alone. The
    query must have its ``offset_units`` and ``fans``."""
    k, beams = query.offsets.shape
    chunks, parts = _chunks_and_parts(k, beams)
    if parts <= 1:
        return None
    args = _kernel_args(query, walls, robots, sight, *out)
    return RowsInFlight(helpers(parts - 1).start(_cast_rows, args, chunks, parts - 1,
                                                 first_row // CHUNK_ROBOTS))


def _kernel_args(query: RangerQuery, walls: WallIndex, robots: RobotIndex, sight: SightLists,
                 ranges: np.ndarray, hit_owner: np.ndarray) -> tuple:
    return (tuple(query), tuple(walls.grid), tuple(walls.near), walls.reach, tuple(robots),
            tuple(sight), ranges, hit_owner)


def _chunks_and_parts(k: int, beams: int) -> tuple[int, int]:
    """The chunks of a scan of ``k`` robots and the threads it is worth."""
    chunks = (k + CHUNK_ROBOTS - 1) // CHUNK_ROBOTS
    return chunks, min(get_num_threads(), chunks, k * beams // MIN_BEAMS_PER_PART)
