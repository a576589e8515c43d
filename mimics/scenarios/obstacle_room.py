"""A 12 x 10 m room with obstacles and robots without goals, to explore or deploy in.

A teaching scenario for exploration and coverage: boxes, a pillar and a
partition wall, and robots placed at random in the free space (a greedy placement
that corners itself is drawn again from the next stream): the run's
seed draws the placement (``fixed = true``: always the layout of seed 0).
"""

import numpy as np

from mimics.world.errors import ScenarioError
from mimics.world.maps import Map
from mimics.world.placement import random_placement
from mimics.world.robot_types import PIONEER_2DX
from mimics.world.scenario import Scenario, Settings
from mimics.world.streams import stream

SEED_CHANGES = "every robot's random placement and heading (fixed = true: the layout of seed 0)"

WIDTH, HEIGHT = 12.0, 10.0
# obstacles as (x, y, width, height) boxes
BOXES = ((2.0, 2.0, 1.5, 1.0), (7.5, 1.5, 1.0, 2.0), (5.5, 5.0, 1.0, 1.0),
         (2.5, 7.0, 2.0, 0.8), (9.0, 6.5, 1.2, 1.5))
PARTITION = ((4.0, 10.0, 4.0, 8.5), (8.0, 0.0, 8.0, 0.8))  # walls from the sides


ATTEMPTS = 50  # placements tried in turn, each from a stream of its own


def _room() -> Map:
    walls = list(Map.box(WIDTH, HEIGHT).segments.tolist())
    for x, y, w, h in BOXES:
        walls += [(x, y, x + w, y), (x + w, y, x + w, y + h), (x + w, y + h, x, y + h),
                  (x, y + h, x, y)]
    walls += list(PARTITION)
    return Map(np.array(walls), (0.0, 0.0, WIDTH, HEIGHT), name="obstacle room")


def scenario(robots: int = 6, seed: int = 0, time_limit: float = 120.0,
             fixed: bool = False) -> Scenario:
    """``robots`` Pioneer2DX at random free poses drawn from ``seed`` (0 when ``fixed``),
    no goals."""
    if isinstance(robots, bool) or not isinstance(robots, int) or not 1 <= robots <= 60:
        raise ScenarioError(f"obstacle_room: robots must be a whole number from 1 to 60, "
                            f"got {robots!r}")
    room = _room()
    layout_seed = 0 if fixed else seed
    for attempt in range(ATTEMPTS):  # a greedy placement of many robots may corner itself
        try:
            poses = random_placement(robots, PIONEER_2DX, room,
                                     stream(layout_seed, "obstacle_room.placement", attempt),
                                     min_spacing=1.0, clearance=0.3)
            break
        except ScenarioError:
            if attempt == ATTEMPTS - 1:
                raise
    rows = np.column_stack([poses, np.zeros(robots)])
    return Scenario.from_matrix(rows, room, PIONEER_2DX, settings=Settings(time_limit=time_limit),
                                name="obstacle_room")
