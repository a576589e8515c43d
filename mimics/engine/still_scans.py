"""Robots that stand still among still neighbours: their scans sweep what they may see.

A dispersion settles: in the Cave, after about 155 of the paper's 600
simulated seconds, no robot's centre moves again; the robots only turn on
the spot. A robot's sight then depends on headings alone (see
``point_cull.py``), so once it and every robot within its range have
stood still for ``SETTLE_STEPS`` steps, :class:`StillScans` lists the walls
and robots it may see first, and the ranger sweeps those instead of
everything near it, until one of them moves. "Still" is exact: the centre's
coordinates are the same floats as at the step before. A scan is the same,
bit for bit, with the lists or without them.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mimics.engine.point_cull import SightLists, sight_lists
from mimics.engine.robot_index import RobotIndex
from mimics.engine.spatial_index import SegmentGrid, cell_span
from mimics.engine.wall_index import WallIndex, near_cell_of

SETTLE_STEPS = 5  # steps a neighbourhood stands still before its lists are made (~50 us each)


@njit(cache=True)
def _settle(centers: np.ndarray, before: np.ndarray, solid_before: np.ndarray,
            still: np.ndarray, pinned: np.ndarray, max_range: np.ndarray,
            robots: tuple) -> int:
    """Count each robot's still steps, unpin those whose neighbourhood moved; returns
    how many robots are due for lists. ``before`` and ``solid_before`` become this step's.

    A neighbour moved when it is seen (in the robot index) and its centre changed
    while within range of the robot, at its old centre or its new one. A change in
    who is seen unpins everyone.
    """
    index = RobotIndex(*robots)
    n = centers.shape[0]
    solid = np.zeros(n, dtype=np.bool_)
    solid[index.grid_items] = True
    moved = np.zeros(n, dtype=np.bool_)
    movers, shift = 0, 0.0
    for j in range(n):
        moved[j] = centers[j, 0] != before[j, 0] or centers[j, 1] != before[j, 1]
        if solid[j] != solid_before[j]:
            movers, shift = n, math.inf  # unpin all
        elif moved[j] and solid[j]:
            movers += 1
            shift = max(shift, math.hypot(centers[j, 0] - before[j, 0],
                                          centers[j, 1] - before[j, 1]))
    due = 0
    nx, ny = index.shape[0], index.shape[1]
    for i in range(n):
        settled = not moved[i] and math.isfinite(shift)
        if settled and movers:
            ox, oy = centers[i, 0], centers[i, 1]
            span = max_range[i] + index.max_radius + shift
            ix0, ix1 = cell_span(ox - span, ox + span, index.origin[0], index.cell, nx)
            iy0, iy1 = cell_span(oy - span, oy + span, index.origin[1], index.cell, ny)
            for iy in range(iy0, iy1 + 1):
                for p in range(index.grid_start[iy * nx + ix0],
                               index.grid_start[iy * nx + ix1 + 1]):
                    j = index.grid_items[p]
                    if moved[j]:
                        reach = (max_range[i] + index.radius[j]) * (1.0 + 1e-9) + 1e-9
                        if min(math.hypot(centers[j, 0] - ox, centers[j, 1] - oy),
                               math.hypot(before[j, 0] - ox, before[j, 1] - oy)) <= reach:
                            settled = False
        if settled:
            still[i] += 1
        else:
            still[i] = 0
            pinned[i] = False
        if still[i] >= SETTLE_STEPS and not pinned[i] and max_range[i] > 0.0:
            due += 1
        before[i, 0], before[i, 1] = centers[i, 0], centers[i, 1]
        solid_before[i] = solid[i]
    return due


@njit(cache=True)
def _pin(centers: np.ndarray, still: np.ndarray, pinned: np.ndarray, max_range: np.ndarray,
         inner: np.ndarray, near_lists: tuple, robots: tuple, lists: tuple
         ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """New CSR lists: the pinned robots' kept, those due made (``pinned`` set for them)."""
    near, index = SegmentGrid(*near_lists), RobotIndex(*robots)
    old = SightLists(*lists)
    n = centers.shape[0]
    nx, ny = index.shape[0], index.shape[1]
    wall_start = np.zeros(n + 1, dtype=np.int64)
    robot_start = np.zeros(n + 1, dtype=np.int64)
    wall_items = np.empty(0, dtype=np.int64)
    robot_items = np.empty(0, dtype=np.int64)
    made_walls = [np.empty(0, dtype=np.int64) for _ in range(0)]
    made_robots = [np.empty(0, dtype=np.int64) for _ in range(0)]
    made = np.full(n, -1, dtype=np.int64)
    candidates = np.empty(index.grid_items.shape[0], dtype=np.int64)
    for i in range(n):
        ox, oy = centers[i, 0], centers[i, 1]
        cell = near_cell_of(near, ox, oy)
        if pinned[i] or still[i] < SETTLE_STEPS or max_range[i] <= 0.0 or cell < 0:
            continue
        # the robots the ranger would list: those of the index cells within range
        span = max_range[i] + index.max_radius
        ix0, ix1 = cell_span(ox - span, ox + span, index.origin[0], index.cell, nx)
        iy0, iy1 = cell_span(oy - span, oy + span, index.origin[1], index.cell, ny)
        found = 0
        for iy in range(iy0, iy1 + 1):
            for p in range(index.grid_start[iy * nx + ix0], index.grid_start[iy * nx + ix1 + 1]):
                candidates[found] = index.grid_items[p]
                found += 1
        walls, seen = sight_lists(ox, oy, max_range[i], i,
                                  near.cell_items[near.cell_start[cell]:near.cell_start[cell + 1]],
                                  near.segments, candidates[:found], index.centers, index.radius,
                                  inner)
        made[i] = len(made_walls)
        made_walls.append(walls)
        made_robots.append(seen)
        pinned[i] = True
    for fill in (False, True):
        if fill:
            wall_items = np.empty(wall_start[n], dtype=np.int64)
            robot_items = np.empty(robot_start[n], dtype=np.int64)
        for i in range(n):
            if made[i] >= 0:
                walls, seen = made_walls[made[i]], made_robots[made[i]]
            elif pinned[i]:
                walls = old.wall_items[old.wall_start[i]:old.wall_start[i + 1]]
                seen = old.robot_items[old.robot_start[i]:old.robot_start[i + 1]]
            else:
                continue
            if fill:
                wall_items[wall_start[i]:wall_start[i + 1]] = walls
                robot_items[robot_start[i]:robot_start[i + 1]] = seen
            else:
                wall_start[i + 1] = walls.shape[0]
                robot_start[i + 1] = seen.shape[0]
        if not fill:
            for i in range(n):
                wall_start[i + 1] += wall_start[i]
                robot_start[i + 1] += robot_start[i]
    return wall_start, wall_items, robot_start, robot_items


class StillScans:
    """Keeps the sight lists of the robots of one run that stand still.

    Args:
        max_range: ``(n,)`` each robot's ranger range (0: none).
        inner: ``(n,)`` each robot's inscribed radius (its smaller half size).
    """

    def __init__(self, max_range: np.ndarray, inner: np.ndarray) -> None:
        n = max_range.shape[0]
        self._max_range, self._inner = max_range, inner
        self._before = np.full((n, 2), np.nan)  # the centres at the last call
        self._solid_before = np.zeros(n, dtype=np.bool_)
        self._still = np.zeros(n, dtype=np.int64)  # steps each neighbourhood stood still
        self._pinned = np.zeros(n, dtype=np.bool_)
        none = np.zeros(n + 1, dtype=np.int64)
        empty = np.zeros(0, dtype=np.int64)
        self.lists = SightLists(self._pinned, none, empty, none, empty)

    def update(self, centers: np.ndarray, walls: WallIndex, robots: RobotIndex) -> SightLists:
        """The lists for the scans of this step (call once per step, before they are
        traced). ``centers``: ``(n, 2)`` C-contiguous, every robot's."""
        due = _settle(centers, self._before, self._solid_before, self._still, self._pinned,
                      self._max_range, tuple(robots))
        if due:
            self.lists = SightLists(self._pinned, *_pin(
                centers, self._still, self._pinned, self._max_range, self._inner,
                tuple(walls.near), tuple(robots), tuple(self.lists)))
        return self.lists
