"""Stage's Cave: 16 x 16 m, 100 Pioneer2DX between the north and west sides, no goals.

The benchmark of R. Vaughan's "Massively multi-robot simulation in Stage"
that the MiMicS paper re-ran (section 5.1): the ``cave_filled.png`` bitmap
vectorised with Stage's scaling, the robots at the start poses of Stage's
``cave.world``, for a deployment algorithm (``deployment``). Needs the Stage
data (``mimics data get stage``). Unlike Stage, robots collide with the walls.
The run's seed jitters each start by up to ``jitter`` m along x and y and its
heading by up to ``yaw_jitter`` rad; ``fixed = true`` keeps Stage's poses
exactly (the paper's experiment does).
"""

import numpy as np

from mimics.world.data_folder import find_stage_file
from mimics.world.errors import ScenarioError
from mimics.world.map_files import load_map
from mimics.world.robot_types import PIONEER_2DX
from mimics.world.scenario import Scenario, Settings
from mimics.world.stage_worlds import stage_robot_poses
from mimics.world.start_jitter import jitter_start

SEED_CHANGES = ("start jitter: up to 0.05 m and 0.1 rad per robot from Stage's poses (jitter, "
                "yaw_jitter; fixed = true: Stage's poses)")
ROBOTS = 100


def scenario(robots: int = ROBOTS, time_limit: float = 600.0, jitter: float = 0.05,
             yaw_jitter: float = 0.1, seed: int = 0, fixed: bool = False) -> Scenario:
    """The first ``robots`` (at most 100) of cave.world's robots, for ``time_limit`` s, each
    start jittered from ``seed`` (none when ``fixed``)."""
    if isinstance(robots, bool) or not isinstance(robots, int) or not 1 <= robots <= ROBOTS:
        raise ScenarioError(f"cave: robots must be a whole number from 1 to {ROBOTS}, "
                            f"got {robots!r}")
    poses = stage_robot_poses(find_stage_file("cave.world"))[:robots]
    rows = np.column_stack([poses, np.zeros(len(poses))])
    built = Scenario.from_matrix(rows, load_map("stage:cave"), PIONEER_2DX,
                                 settings=Settings(dt=0.1, time_limit=time_limit), name="cave")
    return built if fixed else jitter_start(built, seed, "cave.start", jitter, yaw_jitter)
