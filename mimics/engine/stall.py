"""Deadlock and livelock detection over sliding windows of recent history.

Deadlock: a robot with a goal, not at it, whose every position over the last
``deadlock_window`` seconds lies within ``deadlock_distance`` of where it is
now. Livelock: a robot with a goal that is not in deadlock but is no closer to
its goal (by at least ``livelock_progress``) than ``livelock_window`` seconds
ago: it keeps moving without making progress.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from mimics.engine.state import WorldState
from mimics.world.limits import steps_for
from mimics.world.scenario import Settings


class StallFlags(NamedTuple):
    """Robots whose deadlock or livelock began (new) or ended this step."""

    deadlock_started: np.ndarray
    livelock_started: np.ndarray
    livelock_ended: np.ndarray
    deadlock_ended: np.ndarray
    changes: int = 0  # how many flags are set in all: 0 lets the caller skip the rest


class StallDetector:
    """Keeps ring buffers of positions and goal distances, one row per step."""

    def __init__(self, settings: Settings, n: int) -> None:
        self.deadlock_steps = max(1, steps_for(settings.deadlock_window, settings.dt))
        self.livelock_steps = max(1, steps_for(settings.livelock_window, settings.dt))
        self.settings = settings
        self._limit = float(settings.deadlock_distance)  # the screen's arguments, typed once
        self._progress = float(settings.livelock_progress)
        self._positions = np.zeros((self.deadlock_steps + 1, n, 2))
        self._distances = np.zeros((self.livelock_steps + 1, n))
        self._count = 0

    def update(self, state: WorldState, distance: np.ndarray | None = None,
               active: np.ndarray | None = None) -> StallFlags:
        """Record the current positions and return the changes of stall state.

        ``distance`` (``state.goal_distance()``) and ``active`` (``state.active``)
        may be passed when the caller already has them this step.
        """
        if distance is None:
            distance = state.goal_distance()
        if active is None:
            active = state.active
        quiet = _record_and_screen(self._positions, self._distances, self._count, state.pose,
                                   distance, active, state.in_deadlock, state.in_livelock,
                                   self.deadlock_steps, self.livelock_steps, self._limit,
                                   self._progress)
        self._count += 1
        if quiet:  # nobody stalled, before or now (nearly every step)
            return self._quiet(state.n)
        now = state.pose[:, :2]
        candidates = active & ~np.isnan(distance)
        count = np.count_nonzero
        # None: nobody (an all-False mask not made); a full window is checked only then
        deadlocked: np.ndarray | None = None
        livelocked: np.ndarray | None = None
        if self._count > self.deadlock_steps and count(candidates):
            found = self._deadlocked(now, candidates)
            deadlocked = found if count(found) else None
        if self._count > self.livelock_steps:
            oldest = self._distances[self._count % len(self._distances)]
            found = candidates & (distance > oldest - self.settings.livelock_progress)
            if deadlocked is not None:
                found &= ~deadlocked
            livelocked = found if count(found) else None
        if (deadlocked is None and livelocked is None and not count(state.in_deadlock)
                and not count(state.in_livelock)):
            # nobody stalled, before or now: every flag below would be all False and
            # the stall state would stay all False
            return self._quiet(state.n)
        none = np.zeros(state.n, dtype=bool)
        if deadlocked is None:
            deadlocked = none
        if livelocked is None:
            livelocked = none

        flags = StallFlags(
            deadlock_started=deadlocked & ~state.in_deadlock,
            livelock_started=livelocked & ~state.in_livelock,
            livelock_ended=state.in_livelock & ~livelocked & active,
            deadlock_ended=state.in_deadlock & ~deadlocked & active,
        )
        flags = flags._replace(changes=sum(np.count_nonzero(f) for f in flags[:4]))
        state.in_deadlock[:] = deadlocked | (state.in_deadlock & ~active)
        state.in_livelock[:] = livelocked | (state.in_livelock & ~active)
        return flags

    @staticmethod
    def _quiet(n: int) -> StallFlags:
        quiet = np.zeros(n, dtype=bool)
        quiet.flags.writeable = False  # one array for the four flags: read-only
        return StallFlags(quiet, quiet, quiet, quiet)

    def _deadlocked(self, now: np.ndarray, candidates: np.ndarray) -> np.ndarray:
        """Candidates whose every position in the window lies within the distance of ``now``.

        Exact, but cheap for moving robots: the oldest position of the window
        is one of the positions checked, so a robot farther than the distance
        from it cannot be in deadlock and its window is not scanned. Only the
        robots left (nearly still ones) get the full O(window) check, on the
        very same numbers as a check of every robot would use.
        """
        limit = self.settings.deadlock_distance
        oldest = self._positions[self._count % len(self._positions)]
        near = np.hypot(oldest[:, 0] - now[:, 0], oldest[:, 1] - now[:, 1]) <= limit
        ids = (candidates & near).nonzero()[0]
        deadlocked = np.zeros(len(now), dtype=bool)
        if ids.size:
            offsets = self._positions[:, ids] - now[None, ids]
            spread = np.max(np.hypot(offsets[..., 0], offsets[..., 1]), axis=0)
            deadlocked[ids] = spread <= limit
        return deadlocked

    def window_start(self, kind: str, now: float) -> float:
        """The time a stall found now began (the start of its window)."""
        steps = self.deadlock_steps if kind == "deadlock" else self.livelock_steps
        return max(0.0, now - steps * self.settings.dt)


#: Relative and absolute margins of the screen below: a robot this near a bound is
#: left to the exact check, whatever rounding the two computations differ by.
_RELATIVE_MARGIN, _ABSOLUTE_MARGIN = 1e-9, 1e-12


@njit(cache=True)
def _record_and_screen(positions: np.ndarray, distances: np.ndarray, count: int,
                       pose: np.ndarray, distance: np.ndarray, active: np.ndarray,
                       in_deadlock: np.ndarray, in_livelock: np.ndarray, deadlock_steps: int,
                       livelock_steps: int, limit: float, progress: float) -> bool:
    """Write this step's row of the windows (slot ``count``); True when no robot can
    be stalled, before or now.

    A screen, in one call: it may answer False for a robot that the exact
    NumPy check then clears, never True for one that check would flag. A robot
    is let through when it is farther than ``limit`` (and a margin) from where
    it was a deadlock window ago, and nearer its goal by more than ``progress``
    (and a margin) than a livelock window ago; NaN compares false in both
    checks, as in the exact one.
    """
    slot_d, slot_l = count % positions.shape[0], count % distances.shape[0]
    n = pose.shape[0]
    for i in range(n):
        positions[slot_d, i, 0] = pose[i, 0]
        positions[slot_d, i, 1] = pose[i, 1]
        distances[slot_l, i] = distance[i]
    count += 1
    oldest_d, oldest_l = count % positions.shape[0], count % distances.shape[0]
    near = limit * (1.0 + _RELATIVE_MARGIN) + _ABSOLUTE_MARGIN
    for i in range(n):
        if in_deadlock[i] or in_livelock[i]:
            return False
        if not active[i] or math.isnan(distance[i]):
            continue
        if count > deadlock_steps and math.hypot(positions[oldest_d, i, 0] - pose[i, 0],
                                                 positions[oldest_d, i, 1] - pose[i, 1]) <= near:
            return False
        if count > livelock_steps:
            bound = distances[oldest_l, i] - progress
            if distance[i] > bound - abs(bound) * _RELATIVE_MARGIN - _ABSOLUTE_MARGIN:
                return False
    return True
