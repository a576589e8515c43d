"""The rangers' scans of one run, traced when first read (``WorldState.scan``).

Sensing only notes which robots scan and when; the rays are cast at the first
read of ``state.scan`` or ``state.scan_hit`` after it, from that same state
(nothing moves before the algorithm and the observers have read). A step whose
readers read no scan casts no ray, as Stage updates no sensor that has no
subscriber. The ranger's noise is keyed by step, robot and beam
(:class:`~mimics.engine.noise_streams.RangerNoise`), so a scan's noise does
not depend on which earlier scans were read, nor on which other robots scan.

A robot's own read (``robot.scan``, per-robot algorithms) asks for its row
only: the first one starts the trace on the helper threads, so the rays of
the next robots are cast while the algorithm runs for this one; a later read
whose row is not traced yet traces the last rows left (the helper goes on
from the front) until its own is done, so that the helper goes on beside the
next robots' Python. Every row is the same, bit for bit, as in one whole trace.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from mimics.engine.compiling import waiting
from mimics.engine.noise_streams import RangerNoise
from mimics.engine.ranging.point_cull import SightLists
from mimics.engine.ranging.ranger import RangerQuery, RowsInFlight, start_beams, trace_beams
from mimics.engine.ranging.still_scans import StillScans
from mimics.engine.ranging.wall_index import WallIndex
from mimics.engine.robot_index import RobotIndex
from mimics.engine.state import TypeArrays, WorldState

_ray_part_elsewhere: list[Callable[[], None]] = []


def ray_part_compiling_elsewhere(wait: Callable[[], None]) -> None:
    """Tell the scanner that another process compiles the ray part: the first scan
    calls ``wait`` and then loads the part from the cache, not compiling it twice."""
    _ray_part_elsewhere.append(wait)


def forget_ray_part() -> None:
    """Drop the waits (the run is over, the compiling process stopped: a later scan of
    this process compiles the part here)."""
    _ray_part_elsewhere.clear()


def await_ray_part() -> None:
    """Before a scan: wait for the processes compiling the ray part, if any (the wait
    goes on the compile clock, not on the run's time)."""
    while _ray_part_elsewhere:
        with waiting():  # a compile of this process meanwhile counts once
            _ray_part_elsewhere.pop()()



class Scanner:
    """Traces the scans of one run's rangers on demand.

    Args:
        state: the run's state (its scan buffers are filled).
        types: the robots' type arrays.
        noise: the rangers' noise draws (a stretch of their stream per step).
        walls: gives the walls indexed for the ranger (built on first use).
        robots: gives the index of the robots others can see, for this step.
    """

    def __init__(self, state: WorldState, types: TypeArrays, noise: RangerNoise,
                 walls: Callable[[], WallIndex], robots: Callable[[], RobotIndex]) -> None:
        self._state, self._types = state, types
        self._noise = noise
        self._walls, self._robots = walls, robots
        self._has_ranger = types.beam_count > 0
        self._still = StillScans(types.max_range, types.beam_count,
                                 np.minimum(types.half_length, types.half_width))
        self._ids = np.zeros(0, dtype=np.int64)  # the robots of the last sensing's scan
        self._beams: tuple[np.ndarray, ...] = ()  # the beams of the robots that scan...
        self._beams_key: bytes | None = None  # ...as _query keys them (b"": everyone)
        self._flight: RowsInFlight | None = None  # a trace the helper threads go on with

    def sense(self) -> None:
        """Note the robots that scan now: their rays wait for the first read (before the
        robots move, so ``state.step`` is still this sensing's step then)."""
        state = self._state
        self._ids = (state.active & self._has_ranger).nonzero()[0]
        self.drop()  # (the step has ended any trace under way already)
        state.pending_scan = self if self._ids.size else None

    # -- PendingScan (state.py): what the state asks for when the scan is read -------

    def trace_all(self) -> None:
        """Cast the rays of the last sensing into the state's scan buffers."""
        if self._flight is not None:
            self.drop()
        else:
            self._trace()

    def trace_row(self, robot: int) -> bool:
        """Trace ``robot``'s row; when every robot scans without noise, the helper
        threads trace the next rows while the caller reads this one (a per-robot
        algorithm's turn). A row not traced yet when read is waited for while this
        thread traces the last rows left: finishing them all here, with the helper,
        would leave the next robots' Python without it (the Cave's per-robot run, while
        its robots move: 1 to 12% faster, the most when the machine is slow). True if
        every row is traced now."""
        if self._flight is not None:
            if self._flight.row_done(robot):
                return False
            if self._flight.looks:
                self._flight.help_until(robot)
                return False
            self.drop()  # no look is trusted here: a help per read would cost a call each
            return True
        state = self._state
        prepared = self._query()
        if self._ids.size == state.n and "sigma_range" not in self._types.noisy:
            query, walls, robots, sight = prepared
            self._flight = start_beams(query, walls, robots,
                                       (state.scan_buffer, state.scan_hit_buffer), sight, robot)
            if self._flight is not None:
                return False
        self._trace(prepared)
        return True

    def drop(self) -> None:
        """End the trace under way, if any: no thread writes the buffers afterwards."""
        flight, self._flight = self._flight, None
        if flight is not None:
            flight.finish()

    def walls_changed(self) -> None:
        """The run's walls changed (an edit): the trace under way ends, and what robots
        standing still could see is forgotten (their sight lists hold the old walls)."""
        self.drop()
        types = self._types
        self._still = StillScans(types.max_range, types.beam_count,
                                 np.minimum(types.half_length, types.half_width))

    def _query(self) -> tuple[RangerQuery, WallIndex, RobotIndex, SightLists]:
        """The last sensing's beams, walls, robots and sight lists (waits for the ray
        kernel's compile if another process is at it)."""
        await_ray_part()
        state, types, ids = self._state, self._types, self._ids
        # every robot scanning (the usual case): whole arrays, no gathering copies
        everyone = ids.size == state.n
        rows = slice(None) if everyone else ids
        # the scanning robots' beams change only with the robots: gathered once for them
        # (the Hospital's 2,000 robots once one has stopped: 9 MB of copies a step)
        key = b"" if everyone else ids.tobytes()
        if self._beams_key != key:
            self._beams = (types.beam_offsets[rows], types.max_range[rows],
                           ids.astype(np.int64, copy=False), types.beam_units[rows],
                           types.beam_fans[rows])
            self._beams_key = key
        beams = self._beams
        query = RangerQuery(np.ascontiguousarray(state.pose[rows, :2]),
                            np.ascontiguousarray(state.pose[rows, 2]), *beams)
        walls, robots = self._walls(), self._robots()
        return query, walls, robots, self._still.update(robots.centers, walls, robots)

    def _trace(self, prepared: tuple[RangerQuery, WallIndex, RobotIndex, SightLists] | None = None
               ) -> None:
        """Cast every ray of the last sensing into the state's scan buffers (``prepared``:
        what ``_query`` gave for it, if called already: it updates the sight lists, once
        a step)."""
        query, walls, robots, sight = self._query() if prepared is None else prepared
        state, types, ids = self._state, self._types, self._ids
        everyone = ids.size == state.n
        rows = slice(None) if everyone else ids
        scan, hit = state.scan_buffer, state.scan_hit_buffer
        if everyone:  # the kernel writes straight into the state
            trace_beams(query, walls, robots, (scan, hit), sight)
            ranges = scan
        else:
            ranges, hits = trace_beams(query, walls, robots, sight=sight)
        if "sigma_range" in types.noisy:  # known once per run: no test per step
            self._noise.add(ranges, hit if everyone else hits, query.max_range,
                            types.sigma_range[rows], state.step, ids)
        if not everyone:
            scan[rows], hit[rows] = ranges, hits
