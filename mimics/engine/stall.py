"""Deadlock and livelock detection over sliding windows of recent history.

Deadlock: a robot with a goal, not at it, whose every position over the last
``deadlock_window`` seconds lies within ``deadlock_distance`` of where it is
now. Livelock: a robot with a goal that is not in deadlock but is no closer to
its goal (by at least ``livelock_progress``) than ``livelock_window`` seconds
ago: it keeps moving without making progress.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

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
        self._positions = np.zeros((self.deadlock_steps + 1, n, 2))
        self._distances = np.zeros((self.livelock_steps + 1, n))
        self._count = 0

    def update(self, state: WorldState, distance: np.ndarray | None = None,
               active: np.ndarray | None = None) -> StallFlags:
        """Record the current positions and return the changes of stall state.

        ``distance`` (``state.goal_distance()``) and ``active`` (``state.active``)
        may be passed when the caller already has them this step.
        """
        slot_d = self._count % len(self._positions)
        slot_l = self._count % len(self._distances)
        now = state.pose[:, :2]
        self._positions[slot_d] = now
        if distance is None:
            distance = state.goal_distance()
        if active is None:
            active = state.active
        self._distances[slot_l] = distance
        self._count += 1
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
            # nobody stalled, before or now (nearly every step): every flag below would
            # be all False and the stall state would stay all False
            quiet = np.zeros(state.n, dtype=bool)
            quiet.flags.writeable = False  # one array for the four flags: read-only
            return StallFlags(quiet, quiet, quiet, quiet)
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
