"""Robots on a circle swap places: each one's goal is the antipodal point.

A teaching scenario for collision avoidance: every straight path crosses the
centre, so driving straight to the goal makes everyone meet there. The
circle stands in a walled square room. The run's seed jitters each start by
up to ``jitter`` m along x and y and its heading by up to ``yaw_jitter`` rad
(goals stay antipodal to the nominal starts); ``fixed = true`` turns it off.
"""

import numpy as np

from mimics.world.errors import ScenarioError
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX
from mimics.world.scenario import Scenario, Settings
from mimics.world.start_jitter import jitter_start

SEED_CHANGES = ("start jitter: up to 0.1 m and 0.1 rad per robot (jitter, yaw_jitter; fixed = "
                "true: none)")


def scenario(robots: int = 8, radius: float = 4.0, time_limit: float = 60.0,
             jitter: float = 0.1, yaw_jitter: float = 0.1, seed: int = 0,
             fixed: bool = False) -> Scenario:
    """``robots`` Pioneer2DX evenly on a circle of ``radius`` m, facing the centre, each
    start jittered from ``seed`` (none when ``fixed``)."""
    if isinstance(robots, bool) or not isinstance(robots, int) or robots < 2:
        raise ScenarioError(f"circle_swap: robots must be a whole number >= 2, got {robots!r}")
    chord = 2 * radius * np.sin(np.pi / robots)
    if chord < 2 * np.hypot(PIONEER_2DX.length, PIONEER_2DX.width) / 2 + 0.2:
        raise ScenarioError(f"circle_swap: {robots} robots are too close on a circle of "
                            f"radius {radius} m (expected a larger radius)")
    angle = 2 * np.pi * np.arange(robots) / robots
    x, y = radius * np.cos(angle), radius * np.sin(angle)
    yaw = np.arctan2(-y, -x)
    rows = np.column_stack([x, y, yaw, np.zeros(robots), -x, -y])
    half = radius + 2.0
    room = Map.box(2 * half, 2 * half, origin=(-half, -half), name="square room")
    built = Scenario.from_matrix(rows, room, PIONEER_2DX,
                                 settings=Settings(time_limit=time_limit), name="circle_swap")
    return built if fixed else jitter_start(built, seed, "circle_swap.start", jitter, yaw_jitter)
