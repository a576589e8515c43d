"""Robots that stand still among still neighbours: their scans sweep what they may see.

A dispersion settles: in the Cave, after about 155 of the paper's 600
simulated seconds, no robot's centre moves again; the robots only turn on
the spot. A robot's sight then depends on headings alone (see
``point_cull.py``), so once it and every robot within its range have
stood still for ``SETTLE_STEPS`` steps, :class:`StillScans` lists the walls
and robots it may see first, with what its scans need of each whatever the
headings (distance bounds and angular spans: ``beam_sweep.wall_plan`` and
``robot_plan``), and the ranger sweeps those instead of everything near it,
until one of them moves. "Still" is exact: the centre's
coordinates are the same floats as at the step before. A scan is the same,
bit for bit, with the lists or without them.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.compiling.kernel_options import INNER
from mimics.engine.ranging.beam_sweep import PLAN, robot_plan, wall_plan
from mimics.engine.ranging.point_cull import SightLists, sight_lists
from mimics.engine.ranging.wall_index import WallIndex, near_cell_of
from mimics.engine.robot_index import RobotIndex, robots_near
from mimics.engine.spatial_index import SegmentGrid

# Hooks by which a process compiling _settle and _pin (the CLI's first run) says whether
# it is done: until then no robot is pinned (its scans are the same bits without lists),
# so the first run does not wait for the still-scan kernels.
_still_part_elsewhere: list[Callable[[], bool]] = []


def still_part_compiling_elsewhere(done: Callable[[], bool]) -> None:
    """Tell the engine that another process compiles the still scans' kernels: robots
    are pinned only once ``done()`` says the compile is over (the kernels then load
    from Numba's cache)."""
    _still_part_elsewhere.append(done)


def still_part_ready() -> bool:
    """Whether the still scans' kernels may be called (compiled here if need be)."""
    while _still_part_elsewhere and _still_part_elsewhere[0]():
        _still_part_elsewhere.pop(0)
    return not _still_part_elsewhere


def forget_still_part() -> None:
    """Drop the hooks (the compiling process was stopped: a later call compiles here)."""
    _still_part_elsewhere.clear()


SETTLE_STEPS = 5  # steps a neighbourhood stands still before its lists are made (~50 us each)
# fewer beams than this: a scan costs too little to pay for its lists (the swarm's 8 e-puck
# beams: the lists' upkeep cost the 10,000-robot swarm 6% where nothing was gained)
MIN_BEAMS = 32


@njit(**INNER)
def _cell(x: float, y: float, index: RobotIndex) -> tuple[int, int]:
    """The index grid's cell of ``(x, y)``, clamped to the grid."""
    ix = smaller(larger(math.floor((x - index.origin[0]) / index.cell), 0.0), index.shape[0] - 1.0)
    iy = smaller(larger(math.floor((y - index.origin[1]) / index.cell), 0.0), index.shape[1] - 1.0)
    return int(ix), int(iy)


@njit(cache=True)
def _settle(centers: np.ndarray, before: np.ndarray, solid_before: np.ndarray,
            still: np.ndarray, pinned: np.ndarray, max_range: np.ndarray,
            robots: tuple) -> int:
    """Count each robot's still steps, unpin those whose neighbourhood moved; returns
    how many robots are due for lists. ``before`` and ``solid_before`` become this step's.

    A robot's neighbourhood moved when a robot that is seen (in the robot index)
    changed its centre within range of it, at the old centre or the new one; the
    test is by cells of the index, a little wider than the range (a table of
    summed counts of the cells holding such centres: O(robots + cells)). A
    change in who is seen unpins everyone.
    """
    index = RobotIndex(*robots)
    n = centers.shape[0]
    nx, ny = index.shape[0], index.shape[1]
    solid = np.zeros(n, dtype=np.bool_)
    solid[index.grid_items] = True
    moved = np.zeros(n, dtype=np.bool_)
    # movers[iy + 1, ix + 1]: centres that moved in cell (ix, iy), then summed up and left
    movers = np.zeros((ny + 1, nx + 1), dtype=np.int64)
    everyone, anyone = False, False
    for j in range(n):
        moved[j] = centers[j, 0] != before[j, 0] or centers[j, 1] != before[j, 1]
        if solid[j] != solid_before[j]:
            everyone = True
        elif moved[j] and solid[j]:
            anyone = True
            for x, y in ((centers[j, 0], centers[j, 1]), (before[j, 0], before[j, 1])):
                ix, iy = _cell(x, y, index)
                movers[iy + 1, ix + 1] += 1
    if anyone:
        for iy in range(1, ny + 1):
            for ix in range(1, nx + 1):
                movers[iy, ix] += movers[iy - 1, ix] + movers[iy, ix - 1] - movers[iy - 1, ix - 1]
    # a mover within range lies at most this many cells away along each axis (with room
    # for the rounding of the cells' bounds)
    reach = (np.max(max_range) + index.max_radius) / index.cell if n else 0.0
    cells = math.ceil(reach * (1.0 + 1e-9) + 1e-9)
    due = 0
    for i in range(n):
        settled = not everyone and not moved[i]
        if settled and anyone:
            ix, iy = _cell(centers[i, 0], centers[i, 1], index)
            x0, x1 = larger(ix - cells, 0), smaller(ix + cells, nx - 1)
            y0, y1 = larger(iy - cells, 0), smaller(iy + cells, ny - 1)
            settled = (movers[y1 + 1, x1 + 1] - movers[y0, x1 + 1] - movers[y1 + 1, x0]
                       + movers[y0, x0]) == 0
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


@njit(**INNER)
def _copy_rows(items: np.ndarray, plan: np.ndarray, start: int, to_items: np.ndarray,
               to_plan: np.ndarray, at: int, count: int) -> None:
    """``to_items[at:at + count] = items[start:start + count]``, and the same rows of the
    plans, as loops: a slice assignment compiles its shape-mismatch error's formatting,
    seconds of a first run's compile for a message that cannot occur here."""
    for row in range(count):
        to_items[at + row] = items[start + row]
        for column in range(to_plan.shape[1]):
            to_plan[at + row, column] = plan[start + row, column]


@njit(**INNER)
def _reserve(items: np.ndarray, plan: np.ndarray, used: int,
             more: int) -> tuple[np.ndarray, np.ndarray]:
    """``items`` and ``plan`` with room for ``more`` after ``used`` (copies, twice as long,
    if needed)."""
    if used + more <= items.shape[0]:
        return items, plan
    size = larger(2 * items.shape[0], used + more)
    grown, grown_plan = np.empty(size, dtype=np.int64), np.empty((size, PLAN))
    _copy_rows(items, plan, 0, grown, grown_plan, 0, used)
    return grown, grown_plan


@njit(**INNER)
def _compact(pinned: np.ndarray, spans: np.ndarray, items: np.ndarray, plan: np.ndarray,
             used: int) -> tuple[np.ndarray, np.ndarray, int]:
    """The pinned robots' lists alone, when the dropped ones take most of ``items``."""
    live = 0
    for i in range(pinned.shape[0]):
        if pinned[i]:
            live += spans[i, 1] - spans[i, 0] + spans[i, 3] - spans[i, 2]
    size = 2 * live + 4096
    if used <= size:
        return items, plan, used
    kept, kept_plan = np.empty(size, dtype=np.int64), np.empty((size, PLAN))
    count = 0
    for i in range(pinned.shape[0]):
        if pinned[i]:
            for k in (0, 2):
                length = spans[i, k + 1] - spans[i, k]
                _copy_rows(items, plan, spans[i, k], kept, kept_plan, count, length)
                spans[i, k], spans[i, k + 1] = count, count + length
                count += length
    return kept, kept_plan, count


@njit(cache=True)
def _pin(centers: np.ndarray, still: np.ndarray, pinned: np.ndarray, max_range: np.ndarray,
         inner: np.ndarray, near_lists: tuple, robots: tuple, spans: np.ndarray,
         items: np.ndarray, plan: np.ndarray, used: int) -> tuple[np.ndarray, np.ndarray, int]:
    """Make the lists of the robots due (``pinned`` and ``spans`` set for them), appended
    to ``items[:used]``, with their plans; returns the items, the plans and how many
    are used."""
    near, index = SegmentGrid(*near_lists), RobotIndex(*robots)
    items, plan, used = _compact(pinned, spans, items, plan, used)
    segments = near.segments
    candidates = np.empty(index.grid_items.shape[0], dtype=np.int64)
    for i in range(centers.shape[0]):
        ox, oy = centers[i, 0], centers[i, 1]
        cell = near_cell_of(near, ox, oy)
        if pinned[i] or still[i] < SETTLE_STEPS or max_range[i] <= 0.0 or cell < 0:
            continue
        # the robots the ranger would list
        found = robots_near(index, ox, oy, max_range[i] + index.max_radius, candidates)
        walls, seen = sight_lists(ox, oy, max_range[i], i,
                                  near.cell_items[near.cell_start[cell]:near.cell_start[cell + 1]],
                                  segments, candidates[:found], index.centers, index.radius,
                                  inner)
        items, plan = _reserve(items, plan, used, walls.shape[0] + seen.shape[0])
        for k, listed in ((0, walls), (2, seen)):
            spans[i, k], spans[i, k + 1] = used, used + listed.shape[0]
            for row in range(listed.shape[0]):
                items[used + row] = listed[row]
            used += listed.shape[0]
        for row in range(spans[i, 0], spans[i, 1]):  # the scans' own numbers, kept
            s = items[row]
            wall_plan(ox, oy, segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3],
                      plan[row])
        for row in range(spans[i, 2], spans[i, 3]):
            r = items[row]
            robot_plan(index.centers[r, 0] - ox, index.centers[r, 1] - oy, index.radius[r],
                       plan[row])
        pinned[i] = True
    return items, plan, used


class StillScans:
    """Keeps the sight lists of the robots of one run that stand still.

    Args:
        max_range: ``(n,)`` each robot's ranger range (0: none).
        beams: ``(n,)`` each robot's number of beams (robots with fewer than
            ``MIN_BEAMS`` are never pinned).
        inner: ``(n,)`` each robot's inscribed radius (its smaller half size).
    """

    def __init__(self, max_range: np.ndarray, beams: np.ndarray, inner: np.ndarray) -> None:
        n = max_range.shape[0]
        # a range of 0 marks the robots never pinned
        self._max_range = np.where(beams >= MIN_BEAMS, max_range, 0.0)
        self._pinnable = bool(self._max_range.any())  # else never a list (asked every step)
        self._inner = inner
        self._before = np.full((n, 2), np.nan)  # the centres at the last call
        self._solid_before = np.zeros(n, dtype=np.bool_)
        self._still = np.zeros(n, dtype=np.int64)  # steps each neighbourhood stood still
        self._used = 0  # items in use (the pinned robots' lists and dropped ones)
        self.lists = SightLists(np.zeros(n, dtype=np.bool_), np.zeros((n, 4), dtype=np.int64),
                                np.zeros(1024, dtype=np.int64), np.zeros((1024, PLAN)))

    def update(self, centers: np.ndarray, walls: WallIndex, robots: RobotIndex) -> SightLists:
        """The lists for the scans of this step (call once per step, before they are
        traced). ``centers``: ``(n, 2)`` C-contiguous, every robot's."""
        pinned, spans, items, plan = self.lists
        if not self._pinnable or (_still_part_elsewhere and not still_part_ready()):
            return self.lists
        if _settle(centers, self._before, self._solid_before, self._still, pinned,
                   self._max_range, tuple(robots)):
            items, plan, self._used = _pin(centers, self._still, pinned, self._max_range,
                                           self._inner, tuple(walls.near), tuple(robots), spans,
                                           items, plan, self._used)
            self.lists = SightLists(pinned, spans, items, plan)
        return self.lists
