"""Robots meet at a crossroads: ``per_arm`` robots queue on each of four arms, each one's
goal on the opposite arm, so every path crosses the middle.

The run's seed jitters each start by up to ``jitter`` m along x and y and its
heading by up to ``yaw_jitter`` rad (goals stay where the nominal starts put
them), so each seed meets a slightly different crossing; ``fixed = true`` turns
it off. The deadlock rule, like every scenario's, is set by the parameters
``deadlock_window`` and ``deadlock_distance`` (a robot that moved less than
``deadlock_distance`` m in ``deadlock_window`` s is removed as deadlocked).

    mimics run scenarios/crossroads.py submissions/alice.py --seed 1 --out runs/crossroads
"""

import numpy as np

from mimics.world.errors import ScenarioError
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX
from mimics.world.scenario import Scenario, Settings
from mimics.world.start_jitter import jitter_start

SEED_CHANGES = "start jitter: up to 0.3 m and 0.2 rad per robot (jitter, yaw_jitter)"


def scenario(per_arm: int = 2, distance: float = 4.0, spacing: float = 1.5,
             time_limit: float = 60.0, jitter: float = 0.3, yaw_jitter: float = 0.2,
             seed: int = 0, fixed: bool = False) -> Scenario:
    """``4 * per_arm`` Pioneer2DX facing the centre, the nearest ``distance`` m from it and
    the others ``spacing`` m behind each other; each start jittered from ``seed``. Goals
    are on the opposite arm, the front robot's the farthest."""
    if isinstance(per_arm, bool) or not isinstance(per_arm, int) or not 1 <= per_arm <= 5:
        raise ScenarioError(f"crossroads: per_arm must be a whole number from 1 to 5, got "
                            f"{per_arm!r}")
    if spacing < 1.0 or distance < 2.0:
        raise ScenarioError("crossroads: expected spacing >= 1 m and distance >= 2 m (robots "
                            "would start touching)")
    rows = []
    for arm in range(4):
        angle = arm * np.pi / 2
        ux, uy = np.cos(angle), np.sin(angle)
        for k in range(per_arm):
            start = distance + k * spacing
            # the front robot goes farthest, so no one parks in the path of those behind
            goal = distance + (per_arm - 1 - k) * spacing
            rows.append([-start * ux, -start * uy, angle, 0.0, goal * ux, goal * uy])
    half = distance + (per_arm - 1) * spacing + 2.0
    room = Map.box(2 * half, 2 * half, origin=(-half, -half), name="crossroads")
    built = Scenario.from_matrix(np.array(rows), room, PIONEER_2DX,
                                 settings=Settings(time_limit=time_limit), name="crossroads")
    return built if fixed else jitter_start(built, seed, "crossroads.start", jitter, yaw_jitter)
