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
(Amanatides-Woo) until their first hit. The compiled kernel
(``ray_kernel.py``) runs the scanning robots in parallel: chunks of rows
taken in turn by the calling thread and up to Numba's thread
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
>>> from mimics.engine.ranging.wall_index import build_wall_index
>>> walls = build_wall_index(np.array([[3.0, -1.0, 3.0, 1.0]]), (-5, -5, 5, 5), reach=8.0)
>>> query = RangerQuery(np.zeros((1, 2)), np.zeros(1), np.array([[0.0, np.pi]]),
...                     np.array([8.0]), np.array([-1]))
>>> ranges, owner = cast_rays(query, walls)
>>> ranges.tolist(), owner.tolist()
([[3.0, 8.0]], [[-1, -2]])
"""

from __future__ import annotations

import numpy as np

from mimics.engine.helper_threads.chunks import LEAD
from mimics.engine.helper_threads.threads import Flight, helpers, helpers_worth, solo_arrays

# "X as X": names callers import from here (the module was one before it was split)
from mimics.engine.ranging.beam_fan import ANGLE_SLACK as ANGLE_SLACK
from mimics.engine.ranging.beam_fan import FAN_COLUMNS, beam_fans, offset_units
from mimics.engine.ranging.beam_fan import fast_atan2 as fast_atan2
from mimics.engine.ranging.beam_sweep import ray_segment_distance as ray_segment_distance
from mimics.engine.ranging.point_cull import SightLists, no_sight_lists
from mimics.engine.ranging.ray_kernel import CHUNK_ROBOTS, _cast_rows
from mimics.engine.ranging.ray_kernel import RangerQuery as RangerQuery
from mimics.engine.ranging.wall_index import WallIndex, coerce_wall_index
from mimics.engine.robot_index import RobotIndex, coerce_robot_index
from mimics.engine.spatial_index import coerce_array

# beams per thread below which a scan runs on the calling thread alone: a spinning
# helper joins within microseconds, a sleeping one within 40 to 70 us (kernel_threads)
MIN_BEAMS_PER_PART = 256
NO_SIGHT_LISTS = no_sight_lists()  # no robot pinned


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
        chunks, helping = _chunks_and_helpers(k, beams)
        if helping:
            helpers(helping).run(_cast_rows, args, chunks, helping)
        else:
            _cast_rows(*args, *solo_arrays(chunks), LEAD, 0)
    return ranges, hit_owner


class RowsInFlight:
    """A trace that helper threads go on with (:func:`start_beams`)."""

    def __init__(self, flight: Flight) -> None:
        self._flight = flight

    def row_done(self, row: int) -> bool:
        """Whether ``row`` is traced (a look, no wait)."""
        return self._flight.done(row // CHUNK_ROBOTS)

    @property
    def looks(self) -> bool:
        """Whether :meth:`row_done` can see a row traced (else it always says no)."""
        return self._flight.looks

    def help_until(self, row: int) -> None:
        """Return once ``row`` is traced, tracing the last rows left here meanwhile."""
        self._flight.help_until(row // CHUNK_ROBOTS)

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
    chunks, helping = _chunks_and_helpers(k, beams)
    if not helping:
        return None
    args = _kernel_args(query, walls, robots, sight, *out)
    return RowsInFlight(helpers(helping).start(_cast_rows, args, chunks, helping,
                                               first_row // CHUNK_ROBOTS))


def _kernel_args(query: RangerQuery, walls: WallIndex, robots: RobotIndex, sight: SightLists,
                 ranges: np.ndarray, hit_owner: np.ndarray) -> tuple:
    return (tuple(query), tuple(walls.grid), tuple(walls.near), walls.reach, tuple(robots),
            tuple(sight), ranges, hit_owner)


def _chunks_and_helpers(k: int, beams: int) -> tuple[int, int]:
    """The chunks of a scan of ``k`` robots and the helper threads it is worth."""
    chunks = (k + CHUNK_ROBOTS - 1) // CHUNK_ROBOTS
    return chunks, helpers_worth(min(chunks, k * beams // MIN_BEAMS_PER_PART))
