"""Stage's Cave: 16 x 16 m, 100 Pioneer2DX between the north and west sides, no goals.

The benchmark of R. Vaughan's "Massively multi-robot simulation in Stage"
that the MiMicS paper re-ran (section 5.1): the ``cave_filled.png`` bitmap
vectorised with Stage's scaling, the robots at the start poses of Stage's
``cave.world``, for a deployment algorithm (``deployment``). Needs the Stage
data (``mimics data get stage``). Unlike Stage, robots collide with the walls.
"""

import numpy as np

from mimics.world.data_folder import find_stage_file
from mimics.world.errors import ScenarioError
from mimics.world.map_files import load_map
from mimics.world.robot_types import PIONEER_2DX
from mimics.world.scenario import Scenario, Settings
from mimics.world.stage_worlds import stage_robot_poses

ROBOTS = 100


def scenario(robots: int = ROBOTS, time_limit: float = 600.0) -> Scenario:
    """The first ``robots`` (at most 100) of cave.world's robots, for ``time_limit`` s."""
    if isinstance(robots, bool) or not isinstance(robots, int) or not 1 <= robots <= ROBOTS:
        raise ScenarioError(f"cave: robots must be a whole number from 1 to {ROBOTS}, "
                            f"got {robots!r}")
    poses = stage_robot_poses(find_stage_file("cave.world"))[:robots]
    rows = np.column_stack([poses, np.zeros(len(poses))])
    return Scenario.from_matrix(rows, load_map("stage:cave"), PIONEER_2DX,
                                settings=Settings(dt=0.1, time_limit=time_limit), name="cave")
