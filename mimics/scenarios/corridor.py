"""Two groups cross in a corridor: each robot's goal is on the other group's side.

A teaching scenario for collision avoidance: half the robots start at the
west end facing east, half at the east end facing west, in rows across a
closed corridor, and every goal is the mirror image of the start. The run's
seed jitters each start by up to ``jitter`` m along x and y and its heading by
up to ``yaw_jitter`` rad (goals stay those of the nominal starts); ``fixed =
true`` turns it off.
"""

import math

import numpy as np

from mimics.world.errors import ScenarioError
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX
from mimics.world.scenario import Scenario, Settings
from mimics.world.start_jitter import jitter_start

SEED_CHANGES = ("start jitter: up to 0.1 m and 0.1 rad per robot (jitter, yaw_jitter; fixed = "
                "true: none)")


def scenario(robots: int = 10, length: float = 16.0, width: float = 3.0,
             spacing: float = 0.8, time_limit: float = 120.0, jitter: float = 0.1,
             yaw_jitter: float = 0.1, seed: int = 0, fixed: bool = False) -> Scenario:
    """``robots`` Pioneer2DX (half each way) in a ``length`` x ``width`` m corridor.

    Robots stand ``spacing`` m apart in rows across the corridor, the first
    column 1 m from the end wall; each start jittered from ``seed`` (none when ``fixed``).
    """
    if isinstance(robots, bool) or not isinstance(robots, int) or robots < 2:
        raise ScenarioError(f"corridor: robots must be a whole number >= 2, got {robots!r}")
    rows = int((width - 0.5) // spacing)
    if rows < 1 or spacing < 0.5:
        raise ScenarioError(f"corridor: width {width} m and spacing {spacing} m leave no room for "
                            "a row of robots (expected width >= spacing + 0.5 and spacing >= 0.5)")
    west = math.ceil(robots / 2)
    columns = math.ceil(west / rows)
    if 1.0 + (columns - 1) * spacing > length / 2 - 1.0:
        raise ScenarioError(f"corridor: {robots} robots do not fit in a {length} m corridor "
                            f"(expected a longer one)")
    k = np.arange(robots)
    side = np.where(k < west, 0, 1)  # 0 starts west, 1 starts east
    j = np.where(side == 0, k, k - west)
    column, row = np.divmod(j, rows)
    y = width / 2 + (row - (rows - 1) / 2) * spacing
    x_west = 1.0 + column * spacing
    x = np.where(side == 0, x_west, length - x_west)
    yaw = np.where(side == 0, 0.0, np.pi)
    rows_matrix = np.column_stack([x, y, yaw, np.zeros(robots), length - x, y])
    built = Scenario.from_matrix(rows_matrix, Map.box(length, width, name="corridor"),
                                 PIONEER_2DX, settings=Settings(time_limit=time_limit),
                                 name="corridor")
    return built if fixed else jitter_start(built, seed, "corridor.start", jitter, yaw_jitter)
