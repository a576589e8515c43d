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

from mimics.world.robot_types import PIONEER_2DX
from mimics.world.scenario import Scenario
from mimics.world.stage_scenarios import StageWorldScenario

SEED_CHANGES = ("start jitter: up to 0.05 m and 0.1 rad per robot from Stage's poses (jitter, "
                "yaw_jitter; fixed = true: Stage's poses)")
ROBOTS = 100
_WORLD = StageWorldScenario("cave", PIONEER_2DX, ROBOTS)


def scenario(robots: int = ROBOTS, time_limit: float = 600.0, jitter: float = 0.05,
             yaw_jitter: float = 0.1, seed: int = 0, fixed: bool = False) -> Scenario:
    """The first ``robots`` (at most 100) of cave.world's robots, for ``time_limit`` s, each
    start jittered from ``seed`` (none when ``fixed``)."""
    return _WORLD.build(robots, time_limit, jitter, yaw_jitter, seed, fixed)
