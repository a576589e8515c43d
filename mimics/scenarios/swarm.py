"""A swarm: N e-pucks packed in the middle of an open arena with pillars, to disperse.

The arena grows with the team so that the density stays the same at any
size (one robot per ``AREA_PER_ROBOT`` square metres of arena; the start is
a packed square lattice ``SPACING`` m apart in the middle). Square pillars
stand on a regular grid across the arena; lattice points that would put a
robot within ``CLEARANCE`` of a pillar are skipped. Pair it with
``dispersion_team`` (or ``dispersion``): the robots see each other with
their eight short infrared beams and spread out. The run's seed draws every
robot's start heading (``fixed = true``: those of seed 0).
"""

import math

import numpy as np

from mimics.world.errors import ScenarioError
from mimics.world.maps import Map
from mimics.world.robot_types import EPUCK
from mimics.world.scenario import Scenario, Settings
from mimics.world.streams import keyed_uniform

SEED_CHANGES = "every robot's start heading (fixed = true: those of seed 0)"

SPACING = 0.1  # m between lattice points: over the e-puck's 0.099 m diagonal, in sight
AREA_PER_ROBOT = 0.25  # m^2 of arena per robot
PILLAR = 0.3  # m, side of a square pillar
PILLAR_PITCH = 3.0  # m between pillar centres
CLEARANCE = 0.05  # m kept between a starting robot's body and a pillar
MAX_SWARM = 100_000


def _pillars(side: float) -> np.ndarray:
    """Centres of the pillars: a grid ``PILLAR_PITCH`` apart, none within 1 m of the fence."""
    ticks = np.arange(PILLAR_PITCH / 2, side - 1.0, PILLAR_PITCH)
    ticks = ticks[ticks > 1.0]
    gx, gy = np.meshgrid(ticks, ticks, indexing="xy")
    return np.column_stack([gx.ravel(), gy.ravel()])


def _arena(side: float, pillars: np.ndarray) -> Map:
    walls = list(Map.box(side, side).segments.tolist())
    h = PILLAR / 2
    for x, y in pillars:
        walls += [(x - h, y - h, x + h, y - h), (x + h, y - h, x + h, y + h),
                  (x + h, y + h, x - h, y + h), (x - h, y + h, x - h, y - h)]
    return Map(np.array(walls), (0.0, 0.0, side, side), name="swarm arena")


def _start(robots: int, side: float, pillars: np.ndarray) -> np.ndarray:
    """The ``robots`` lattice points nearest the centre that keep clear of every pillar."""
    # a lattice a little larger than needed, so that skipped points are made up for
    k = math.ceil(math.sqrt(robots * 1.3)) + 2
    ticks = (np.arange(k) - (k - 1) / 2) * SPACING
    gx, gy = np.meshgrid(ticks + side / 2, ticks + side / 2, indexing="xy")
    xy = np.column_stack([gx.ravel(), gy.ravel()])
    # a robot's reach from its centre: half its diagonal
    reach = math.hypot(EPUCK.length, EPUCK.width) / 2 + CLEARANCE + PILLAR / 2
    if len(pillars):
        # the pillars are a grid (every x tick with every y tick), so a point's nearest
        # pillar in max(|dx|, |dy|) is its nearest x tick with its nearest y tick: the same
        # test as against each pillar, in time linear in the points
        near = np.ones(len(xy), dtype=bool)
        for axis in (0, 1):
            ticks = np.unique(pillars[:, axis])
            above = np.clip(np.searchsorted(ticks, xy[:, axis]), 0, len(ticks) - 1)
            below = np.maximum(above - 1, 0)
            gap = np.minimum(np.abs(xy[:, axis] - ticks[above]), np.abs(xy[:, axis] - ticks[below]))
            near &= gap < reach
        xy = xy[~near]
    order = np.lexsort((xy[:, 0], xy[:, 1], np.round(np.hypot(*(xy - side / 2).T), 9)))
    return xy[order[:robots]]


def scenario(robots: int = 100, seed: int = 0, time_limit: float = 60.0,
             fixed: bool = False) -> Scenario:
    """``robots`` e-pucks packed in the middle of a pillared arena sized for them, no goals.

    Headings are random, robot i's drawn from ``(seed, i)`` (seed 0 when ``fixed``).
    """
    if isinstance(robots, bool) or not isinstance(robots, int) or not 1 <= robots <= MAX_SWARM:
        raise ScenarioError(f"swarm: robots must be a whole number from 1 to {MAX_SWARM}, "
                            f"got {robots!r}")
    side = max(math.sqrt(robots * AREA_PER_ROBOT), 4.0)
    pillars = _pillars(side)
    xy = _start(robots, side, pillars)
    yaw = keyed_uniform(0 if fixed else seed, "swarm.start_yaw", robots, -np.pi, np.pi)
    rows = np.column_stack([xy, yaw, np.zeros(robots), np.full(robots, np.nan),
                            np.full(robots, np.nan)])
    return Scenario.from_matrix(rows, _arena(side, pillars), EPUCK,
                                settings=Settings(time_limit=time_limit), name="swarm")
