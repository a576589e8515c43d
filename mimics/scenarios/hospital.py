"""Stage's Hospital: 140 x 60 m, 2,000 robots of 0.1 m in two blocks across the corridor.

The MiMicS paper's large-scale benchmark (section 5.2): ``hospital.png``
vectorised with Stage's scaling (140 x 60 m centred at (0, 0.5)), and the
start poses of Stage's ``hospital.world``, both blocks of 5 rows x 200 columns
(the file comments out the second one; the paper used both). The robots are
``Swarmbot``: Pioneer2DX dynamics with a 2 m LMS200-like laser. No goals: for
a deployment algorithm. Needs the Stage data (``mimics data get stage``).
The run's seed jitters each start by up to ``jitter`` m along x and y and its
heading by up to ``yaw_jitter`` rad; ``fixed = true`` keeps Stage's poses
exactly (the paper's experiment does).
"""

import numpy as np

from mimics.world.data_folder import find_stage_file
from mimics.world.errors import ScenarioError
from mimics.world.map_files import load_map
from mimics.world.robot_types import SWARMBOT
from mimics.world.scenario import Scenario, Settings
from mimics.world.stage_worlds import stage_robot_poses
from mimics.world.start_jitter import jitter_start

SEED_CHANGES = ("start jitter: up to 0.02 m and 0.1 rad per robot from Stage's poses (jitter, "
                "yaw_jitter; fixed = true: Stage's poses)")
ROBOTS = 2000


def scenario(robots: int = ROBOTS, time_limit: float = 600.0, jitter: float = 0.02,
             yaw_jitter: float = 0.1, seed: int = 0, fixed: bool = False) -> Scenario:
    """The first ``robots`` (at most 2,000) of hospital.world's robots, for ``time_limit`` s,
    each start jittered from ``seed`` (none when ``fixed``)."""
    if isinstance(robots, bool) or not isinstance(robots, int) or not 1 <= robots <= ROBOTS:
        raise ScenarioError(f"hospital: robots must be a whole number from 1 to {ROBOTS}, "
                            f"got {robots!r}")
    poses = stage_robot_poses(find_stage_file("hospital.world"), include_commented=True)
    rows = np.column_stack([poses[:robots], np.zeros(robots)])
    built = Scenario.from_matrix(rows, load_map("stage:hospital"), SWARMBOT,
                                 settings=Settings(dt=0.1, time_limit=time_limit),
                                 name="hospital")
    return built if fixed else jitter_start(built, seed, "hospital.start", jitter, yaw_jitter)
