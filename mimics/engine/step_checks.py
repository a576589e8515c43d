"""The checks after the robots move: the robot index, then in one compiled call the
collisions, the distances to the goals and whether a moved robot left the map or
arrived.

Each is what :func:`mimics.engine.robot_index.index_robots`,
:func:`mimics.engine.collision.collide` and ``WorldState.goal_distance`` compute,
with the same code, so the results are the same bits (tested). Two calls (the index's
kernel, then one for the rest) instead of four with their NumPy glue take
about 30 us less per step, most of a step of a few robots (the paper's
Figure 2 battery is 1,800 such runs). The index stays a call of its own: in
the same kernel it made the first-run compile 2.5 s longer.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from mimics.engine.collision import NONE, WALL, Bodies, _lowest_robot, _lowest_wall
from mimics.engine.robot_index import RobotIndex, index_robots
from mimics.engine.spatial_index import SegmentGrid


class StepChecks(NamedTuple):
    """What :func:`check_moved` found.

    Attributes:
        robots: the index of the solid robots at the new poses.
        with_whom: ``(n,)`` per checked robot, as :func:`collide` gives it (-2 for the others).
        distance: ``(n,)`` every robot's distance to its goal (NaN without one).
        touching: how many checked robots touch something.
        quiet: no checked robot is outside the bounds or within the goal tolerance.
    """

    robots: RobotIndex
    with_whom: np.ndarray
    distance: np.ndarray
    touching: int
    quiet: bool


def check_moved(pose: np.ndarray, half_length: np.ndarray, half_width: np.ndarray,
                radius: np.ndarray, solid: np.ndarray, cell: float, ids: np.ndarray,
                wall_grid: SegmentGrid, goal: np.ndarray,
                bounds: tuple[float, float, float, float], tolerance: float) -> StepChecks:
    """Index the ``solid`` robots, then check robots ``ids`` (ascending) for collisions,
    leaving the map and reaching their goals.

    The engine's own arrays, unchecked: C-contiguous float64 ``pose (n, 3)``,
    ``goal (n, 2)``, sizes and ``radius`` (``np.hypot(half_length, half_width)``),
    bool ``solid``, int64 ``ids``, finite poses for solid and checked robots.
    """
    n = pose.shape[0]
    headings = np.ascontiguousarray(pose[:, 2])
    robots = index_robots(np.ascontiguousarray(pose[:, :2]), headings, half_length, half_width,
                          solid, cell, radius)
    distance = np.empty(n)
    with_whom = np.empty(n, dtype=np.int64)
    xmin, ymin, xmax, ymax = bounds
    touching, quiet = _check_kernel(tuple(robots), headings, half_length, half_width, ids,
                                    tuple(wall_grid), pose, goal, float(xmin), float(ymin),
                                    float(xmax), float(ymax), float(tolerance), distance,
                                    with_whom)
    return StepChecks(robots, with_whom, distance, touching, quiet)


@njit(cache=True)
def _check_kernel(robot_index: tuple, headings: np.ndarray, half_length: np.ndarray,
                  half_width: np.ndarray, ids: np.ndarray, wall_grid: tuple, pose: np.ndarray,
                  goal: np.ndarray, xmin: float, ymin: float, xmax: float, ymax: float,
                  tolerance: float, distance: np.ndarray, with_whom: np.ndarray
                  ) -> tuple[int, bool]:
    """Collisions, distances and the screen of :func:`check_moved` (``robot_index`` and
    ``wall_grid``: a ``RobotIndex``'s and a ``SegmentGrid``'s fields as plain tuples,
    which the dispatcher types in C); returns ``touching`` and ``quiet``."""
    n = pose.shape[0]
    robots, walls = RobotIndex(*robot_index), SegmentGrid(*wall_grid)
    bodies = Bodies(robots.centers, headings, half_length, half_width)
    for i in range(n):
        with_whom[i] = NONE
        distance[i] = np.hypot(goal[i, 0] - pose[i, 0], goal[i, 1] - pose[i, 1])
    touching = 0
    quiet = True
    for i in ids:
        # the collision check of collision._collide_kernel, robot by robot
        wall = _lowest_wall(bodies, i, walls)
        other = _lowest_robot(bodies, i, robots)
        if other >= 0:
            with_whom[i] = other
        elif wall >= 0:
            with_whom[i] = WALL
        if with_whom[i] != NONE:
            touching += 1
        # the goals-and-bounds screen: anyone outside or arrived takes the long way
        x, y = pose[i, 0], pose[i, 1]
        if x < xmin or x > xmax or y < ymin or y > ymax or distance[i] <= tolerance:
            quiet = False
    return touching, quiet
