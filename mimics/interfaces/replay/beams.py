"""Laser beams recomputed from logged poses with the engine's ray kernel (noise-free: the
ranger noise of a run is not logged), against the walls of the frame's step (an edited
run: one wall index per wall set, built when first needed)."""

from __future__ import annotations

import sys
from collections.abc import Sequence

import numba
import numpy as np

from mimics.engine.state import Status
from mimics.interfaces.render import beam_segments
from mimics.world.scenario import Scenario


class BeamCaster:
    """Recomputes one robot's laser beams from logged poses with the engine's ray kernel.

    Args:
        scenario: the run's scenario (walls and robot types).
        wall_sets: the run's wall sets (``ReplayData.walls.sets``); default: the scenario's
            map only. The methods' ``wall_set`` picks one.
    """

    def __init__(self, scenario: Scenario, wall_sets: Sequence[np.ndarray] | None = None
                 ) -> None:
        from mimics.engine.ranging.ranger import RangerQuery, cast_rays
        from mimics.engine.ranging.wall_index import build_wall_index
        from mimics.engine.robot_index import build_robot_index, index_cell
        from mimics.engine.state import TypeArrays

        self._query, self._cast, self._robot_index = RangerQuery, cast_rays, build_robot_index
        self.scenario = scenario
        self.types = TypeArrays.from_scenario(scenario)
        types = self.types
        self.wall_sets = (tuple(wall_sets) if wall_sets is not None
                          else (scenario.map.segments,))
        self._build_walls = build_wall_index
        self._max_range = float(np.max(types.max_range, initial=0.0))
        self._wall_indexes: dict[int, object] = {}
        self.walls = self.wall_index(0)
        self.robot_cell = index_cell(types.max_range, types.half_length, types.half_width)

    def wall_index(self, wall_set: int) -> object:
        """The ray kernel's index of wall set ``wall_set`` (built once, then kept)."""
        index = self._wall_indexes.get(wall_set)
        if index is None:
            index = self._build_walls(self.wall_sets[wall_set], self.scenario.map.bounds,
                                      self._max_range)
            self._wall_indexes[wall_set] = index
        return index

    @classmethod
    def available(cls, scenario: Scenario, wall_sets: Sequence[np.ndarray] | None = None
                  ) -> BeamCaster | None:
        """A caster, or None (after a one-line notice) when the kernel cannot be imported."""
        try:
            return cls(scenario, wall_sets)
        except ImportError as exc:
            print(f"mimics: beams skipped: the engine's ray kernel is unavailable ({exc})",
                  file=sys.stderr)
            return None

    def beams(self, robot: int, pose: np.ndarray, status: np.ndarray, wall_set: int = 0
              ) -> np.ndarray | None:
        """Beam segments ``(b, 2, 2)`` of ``robot`` in the world ``pose``/``status`` with
        the walls of ``wall_set`` (None when the robot is inactive or has no ranger)."""
        types = self.types
        if status[robot] != Status.ACTIVE or types.beam_count[robot] == 0:
            return None
        ids = np.array([robot], dtype=np.int64)
        offsets = types.beam_offsets[ids]
        ranges = self._ranges(ids, offsets, pose, status, wall_set)
        return beam_segments(np.asarray(pose[robot, :2], dtype=np.float64), float(pose[robot, 2]),
                             types.beam_offsets[robot], ranges[0])

    def all_beams(self, pose: np.ndarray, status: np.ndarray, every: int = 1,
                  wall_set: int = 0) -> np.ndarray:
        """Beam segments ``(m, 2, 2)`` of every active robot with a ranger, in one scan:
        every ``every``-th beam of each robot (1: all of them)."""
        types = self.types
        ids = np.flatnonzero((np.asarray(status) == Status.ACTIVE) & (types.beam_count > 0))
        if ids.size == 0:
            return np.zeros((0, 2, 2))
        offsets = np.ascontiguousarray(types.beam_offsets[ids][:, ::max(1, int(every))])
        ranges = self._ranges(ids.astype(np.int64), offsets, pose, status, wall_set)
        pose64 = np.asarray(pose, dtype=np.float64)
        # beam_offsets pads robots with fewer beams by NaN: beam_segments drops those
        return np.concatenate([beam_segments(pose64[r, :2], float(pose64[r, 2]), offsets[k],
                                             ranges[k]) for k, r in enumerate(ids)])

    def _ranges(self, ids: np.ndarray, offsets: np.ndarray, pose: np.ndarray,
                status: np.ndarray, wall_set: int = 0) -> np.ndarray:
        """The ranges ``(len(ids), b)`` of robots ``ids``' beams at ``offsets``."""
        types = self.types
        pose = np.ascontiguousarray(pose, dtype=np.float64)
        if self.scenario.settings.inactive_as_obstacles:
            solid = (status != Status.ESCAPED) & (status != Status.REMOVED)
        else:
            solid = status == Status.ACTIVE
        robots = self._robot_index(np.ascontiguousarray(pose[:, :2]),
                                   np.ascontiguousarray(pose[:, 2]), types.half_length,
                                   types.half_width, solid, cell=self.robot_cell)
        query = self._query(origins=np.ascontiguousarray(pose[ids, :2]),
                            headings=np.ascontiguousarray(pose[ids, 2]),
                            offsets=np.ascontiguousarray(offsets),
                            max_range=types.max_range[ids], robot=ids)
        threads = numba.get_num_threads()
        if ids.size == 1:
            numba.set_num_threads(1)  # one scan: a thread pool only adds launch latency
        try:
            ranges, _ = self._cast(query, self.wall_index(wall_set), robots)
        finally:
            numba.set_num_threads(threads)
        return np.asarray(ranges)
