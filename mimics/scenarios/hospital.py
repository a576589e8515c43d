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

from mimics.world.robot_types import SWARMBOT
from mimics.world.scenario import Scenario
from mimics.world.stage_scenarios import StageWorldScenario

SEED_CHANGES = ("start jitter: up to 0.02 m and 0.1 rad per robot from Stage's poses (jitter, "
                "yaw_jitter; fixed = true: Stage's poses)")
ROBOTS = 2000
_WORLD = StageWorldScenario("hospital", SWARMBOT, ROBOTS, include_commented=True)


def scenario(robots: int = ROBOTS, time_limit: float = 600.0, jitter: float = 0.02,
             yaw_jitter: float = 0.1, seed: int = 0, fixed: bool = False) -> Scenario:
    """The first ``robots`` (at most 2,000) of hospital.world's robots, for ``time_limit`` s,
    each start jittered from ``seed`` (none when ``fixed``)."""
    return _WORLD.build(robots, time_limit, jitter, yaw_jitter, seed, fixed)
