"""The checks after the robots move, in one compiled call on the robot index: the
collisions, the distances to the goals and whether a moved robot left the map or
arrived.

Each is what :func:`mimics.engine.collision.collide` and
``WorldState.goal_distance`` compute, with the same code, so the results are the
same bits (tested). One call instead of three with their NumPy glue takes about
30 us less per step, most of a step of a few robots (the paper's Figure 2
battery is 1,800 such runs). The index stays a call of its own (the engine's
``_robot_index``): in the same kernel it made the first-run compile 2.5 s longer.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from mimics.engine.collision import NONE, Bodies, touching
from mimics.engine.helper_threads.chunks import (
    HELPER,
    LEAD,
    TALLIES,
    begin,
    chunk_done,
    end,
    take,
    tally,
)
from mimics.engine.helper_threads.threads import helpers, helpers_worth, solo_arrays
from mimics.engine.robot_index import RobotIndex
from mimics.engine.spatial_index import SegmentGrid

# robots per chunk: small enough that a hundred robots make chunks for two threads
CHUNK = 24
# robots per thread below which the checks run on the calling thread alone: a hand-over
# to the spinning helper costs a few us (a Cave of 100 robots: 38 us alone, 27 shared)
MIN_ROBOTS_PER_THREAD = 32


class MotionChecks(NamedTuple):
    """What :func:`check_moved` found.

    Attributes:
        with_whom: ``(n,)`` per checked robot, as :func:`collide` gives it (-2 for the others).
        distance: ``(n,)`` every robot's distance to its goal (NaN without one).
        touching: how many checked robots touch something.
        quiet: no checked robot is outside the bounds or within the goal tolerance.
    """

    with_whom: np.ndarray
    distance: np.ndarray
    touching: int
    quiet: bool


def check_moved(robots: RobotIndex, pose: np.ndarray, half_length: np.ndarray,
                half_width: np.ndarray, ids: np.ndarray, wall_grid: SegmentGrid,
                goal: np.ndarray, bounds: tuple[float, float, float, float],
                tolerance: float) -> MotionChecks:
    """Check robots ``ids`` (ascending) for collisions, leaving the map and reaching
    their goals; ``robots``: the index of the solid robots at these poses.

    The engine's own arrays, unchecked: C-contiguous float64 ``pose (n, 3)``,
    ``goal (n, 2)`` and sizes, int64 ``ids``, finite poses for checked robots.
    """
    n, checked = pose.shape[0], ids.shape[0]
    distance = np.empty(n)
    with_whom = np.empty(n, dtype=np.int64)
    xmin, ymin, xmax, ymax = bounds
    args = (tuple(robots), half_length, half_width, ids, tuple(wall_grid), pose, goal,
            float(xmin), float(ymin), float(xmax), float(ymax), float(tolerance), distance,
            with_whom)
    chunks = (checked + CHUNK - 1) // CHUNK
    helping = helpers_worth(checked // MIN_ROBOTS_PER_THREAD)
    if helping:
        share = helpers(helping).run(_check_kernel, args, chunks, helping)
    else:
        control, share = solo_arrays(chunks)
        _check_kernel(*args, control, share, LEAD, 0)
    touching, loud = share[TALLIES[0]], share[TALLIES[1]]
    return MotionChecks(with_whom, distance, int(touching), not loud)


@njit(cache=True, nogil=True)
def _check_kernel(robot_index: tuple, half_length: np.ndarray, half_width: np.ndarray,
                  ids: np.ndarray, wall_grid: tuple, pose: np.ndarray, goal: np.ndarray,
                  xmin: float, ymin: float, xmax: float, ymax: float, tolerance: float,
                  distance: np.ndarray, with_whom: np.ndarray, control: np.ndarray,
                  share: np.ndarray, role: int, until: int) -> None:
    """Collisions, distances and the screen of :func:`check_moved` (``robot_index`` and
    ``wall_grid``: a ``RobotIndex``'s and a ``SegmentGrid``'s fields as plain tuples,
    which the dispatcher types in C), chunks of ``ids`` shared with the helper threads
    that join (``kernel_threads``); tallies the robots touching something and those not
    quiet."""
    n = pose.shape[0]
    robots, walls = RobotIndex(*robot_index), SegmentGrid(*wall_grid)
    headings = np.empty(n)  # a copy by hand: np.ascontiguousarray compiled for 0.45 s
    for i in range(n):
        headings[i] = pose[i, 2]
    bodies = Bodies(robots.centers, headings, half_length, half_width)
    if role != HELPER:  # before any chunk: the screen reads the distances
        for i in range(n):
            with_whom[i] = NONE
            distance[i] = np.hypot(goal[i, 0] - pose[i, 0], goal[i, 1] - pose[i, 1])
    chunks = (ids.shape[0] + CHUNK - 1) // CHUNK
    begin(control, share, role)
    count = 0
    loud = 0
    chunk = take(share, role, until, chunks)
    while chunk >= 0:
        for i in ids[chunk * CHUNK:(chunk + 1) * CHUNK]:
            with_whom[i] = touching(bodies, i, walls, robots)[0]
            if with_whom[i] != NONE:
                count += 1
            # the goals-and-bounds screen: anyone outside or arrived takes the long way
            x, y = pose[i, 0], pose[i, 1]
            if x < xmin or x > xmax or y < ymin or y > ymax or distance[i] <= tolerance:
                loud += 1
        chunk_done(share, chunk)
        chunk = take(share, role, until, chunks)
    tally(share, 0, count)
    tally(share, 1, loud)
    end(share, role, until, chunks)
