"""Laser beams recomputed from logged poses with the engine's ray kernel (noise-free: the
ranger noise of a run is not logged)."""

from __future__ import annotations

import sys

import numba
import numpy as np

from mimics.engine.state import Status
from mimics.interfaces.render import beam_segments
from mimics.world.scenario import Scenario


class BeamCaster:
    """Recomputes one robot's laser beams from logged poses with the engine's ray kernel.

    Args:
        scenario: the run's scenario (walls and robot types).
    """

    def __init__(self, scenario: Scenario) -> None:
        from mimics.engine.ranging.ranger import RangerQuery, cast_rays
        from mimics.engine.ranging.wall_index import build_wall_index
        from mimics.engine.robot_index import build_robot_index, index_cell
        from mimics.engine.state import TypeArrays

        self._query, self._cast, self._robot_index = RangerQuery, cast_rays, build_robot_index
        self.scenario = scenario
        self.types = TypeArrays.from_scenario(scenario)
        types = self.types
        self.walls = build_wall_index(scenario.map.segments, scenario.map.bounds,
                                      float(np.max(types.max_range, initial=0.0)))
        self.robot_cell = index_cell(types.max_range, types.half_length, types.half_width)

    @classmethod
    def available(cls, scenario: Scenario) -> BeamCaster | None:
        """A caster, or None (after a one-line notice) when the kernel cannot be imported."""
        try:
            return cls(scenario)
        except ImportError as exc:
            print(f"mimics: beams skipped: the engine's ray kernel is unavailable ({exc})",
                  file=sys.stderr)
            return None

    def beams(self, robot: int, pose: np.ndarray, status: np.ndarray) -> np.ndarray | None:
        """Beam segments ``(b, 2, 2)`` of ``robot`` in the world ``pose``/``status``
        (None when the robot is inactive or has no ranger)."""
        types = self.types
        if status[robot] != Status.ACTIVE or types.beam_count[robot] == 0:
            return None
        pose = np.ascontiguousarray(pose, dtype=np.float64)
        if self.scenario.settings.inactive_as_obstacles:
            solid = status != Status.ESCAPED
        else:
            solid = status == Status.ACTIVE
        robots = self._robot_index(np.ascontiguousarray(pose[:, :2]),
                                   np.ascontiguousarray(pose[:, 2]), types.half_length,
                                   types.half_width, solid, cell=self.robot_cell)
        ids = np.array([robot], dtype=np.int64)
        query = self._query(origins=np.ascontiguousarray(pose[ids, :2]),
                            headings=np.ascontiguousarray(pose[ids, 2]),
                            offsets=np.ascontiguousarray(types.beam_offsets[ids]),
                            max_range=types.max_range[ids], robot=ids)
        threads = numba.get_num_threads()
        numba.set_num_threads(1)  # one scan: a thread pool only adds launch latency
        try:
            ranges, _ = self._cast(query, self.walls, robots)
        finally:
            numba.set_num_threads(threads)
        return beam_segments(pose[robot, :2], pose[robot, 2], types.beam_offsets[robot],
                             np.asarray(ranges)[0])
