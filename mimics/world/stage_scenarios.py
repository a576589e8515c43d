"""A built-in scenario from one of Stage's worlds: its robots' start poses on its bitmap.

Shared by the ``cave`` and ``hospital`` scenarios (``mimics/scenarios/``): the first
``robots`` start poses of a ``.world`` file, the map vectorised from its bitmap with
Stage's scaling, one robot type, no goals, each start jittered from the run's seed
unless ``fixed``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimics.world.data_folder import find_stage_file
from mimics.world.errors import ScenarioError
from mimics.world.map_files import load_map
from mimics.world.robot_types import RobotType
from mimics.world.scenario import Scenario, Settings
from mimics.world.stage_worlds import stage_robot_poses
from mimics.world.start_jitter import jitter_start


@dataclass(frozen=True)
class StageWorldScenario:
    """What differs between the Stage-world scenarios."""

    name: str  # the scenario's and the map's name (``stage:NAME``), the world file's stem
    robot_type: RobotType
    max_robots: int
    include_commented: bool = False  # robots the .world file comments out count too

    def build(self, robots: int, time_limit: float, jitter: float, yaw_jitter: float,
              seed: int, fixed: bool) -> Scenario:
        """The first ``robots`` of the world's robots for ``time_limit`` s, each start
        jittered from ``seed`` by up to ``jitter`` m and ``yaw_jitter`` rad (none when
        ``fixed``)."""
        if isinstance(robots, bool) or not isinstance(robots, int) \
                or not 1 <= robots <= self.max_robots:
            raise ScenarioError(f"{self.name}: robots must be a whole number from 1 to "
                                f"{self.max_robots}, got {robots!r}")
        poses = stage_robot_poses(find_stage_file(f"{self.name}.world"),
                                  include_commented=self.include_commented)[:robots]
        rows = np.column_stack([poses, np.zeros(len(poses))])
        built = Scenario.from_matrix(rows, load_map(f"stage:{self.name}"), self.robot_type,
                                     settings=Settings(dt=0.1, time_limit=time_limit),
                                     name=self.name)
        if fixed:
            return built
        return jitter_start(built, seed, f"{self.name}.start", jitter, yaw_jitter)
