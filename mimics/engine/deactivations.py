"""How robots leave a run: arrivals, escapes, collisions' marks, stalls and failures.

A part of :class:`~mimics.engine.simulation.Simulation` kept on its own: a
deactivation is recorded during the step (an event, the robot's system
message) and takes effect at the step's end, so that every robot of a step
sees the same world.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.outcome import Event
from mimics.engine.state import Status
from mimics.engine.user_code import UserFailure

if TYPE_CHECKING:
    from mimics.engine.stall import StallDetector
    from mimics.engine.state import WorldState
    from mimics.world.scenario import Scenario


class RobotDeactivations:
    """The Simulation's bookkeeping of robots leaving the run (a mixin of its state)."""

    state: WorldState
    scenario: Scenario
    events: list[Event]
    policy: str
    status: str
    error: str
    _pending: dict[int, Status]
    _stalls: StallDetector
    _ever_deadlocked: np.ndarray
    _ever_livelocked: np.ndarray
    #: the exception of the failure that ended the run under "abort" (None: none)
    user_exception: BaseException | None = None

    def _mark_departures_and_arrivals(self, ids: np.ndarray, distance: np.ndarray) -> None:
        """Mark robots ``ids`` that left the map or are ``distance`` from their goal."""
        state = self.state
        pose, near = state.pose[ids], distance[ids]
        xmin, ymin, xmax, ymax = self.scenario.map.bounds
        x, y = pose[:, 0], pose[:, 1]
        outside = (x < xmin) | (x > xmax) | (y < ymin) | (y > ymax)
        reached = near <= self.scenario.settings.goal_tolerance
        for i in ids[outside].tolist():
            self._mark(i, Status.ESCAPED, "Escaped map", "escaped")
        for i in ids[reached & ~outside].tolist():
            state.goal_time[i] = state.time
            self._mark(i, Status.REACHED_GOAL, "Reached goal", "reached_goal")

    def _check_stalls(self, distance: np.ndarray, active: np.ndarray) -> None:
        state = self.state
        flags = self._stalls.update(state, distance, active)
        if not flags.changes:
            return
        now = state.time
        for i in np.flatnonzero(flags.deadlock_started).tolist():
            self._ever_deadlocked[i] = True
            start = self._stalls.window_start("deadlock", now)
            if self.scenario.settings.deactivate_on_deadlock:
                self._mark(i, Status.DEADLOCK, "Deadlock", "deadlock", start=start)
            else:
                self._event(i, "deadlock", "Deadlock", start=start)
        for i in np.flatnonzero(flags.deadlock_ended).tolist():
            self._event(i, "deadlock_end", "Deadlock ended")
        for i in np.flatnonzero(flags.livelock_started).tolist():
            self._ever_livelocked[i] = True
            self._event(i, "livelock", "Livelock", start=self._stalls.window_start("livelock",
                                                                                    now))
        for i in np.flatnonzero(flags.livelock_ended).tolist():
            self._event(i, "livelock_end", "Livelock ended")

    def _event(self, robot: int, kind: str, detail: str, **extra: Any) -> None:
        self.events.append(Event(self.state.time, robot, kind, detail, **extra))
        current = self.state.system_message[robot]
        self.state.system_message[robot] = f"{current} | {detail}" if current else detail

    def _mark(self, robot: int, status: Status, detail: str, kind: str, **extra: Any) -> None:
        """Record a deactivation now; it takes effect at the end of the step."""
        if robot in self._pending:
            return
        self._pending[robot] = status
        self._event(robot, kind, detail, **extra)

    def _finish_deactivations(self) -> None:
        state = self.state
        for robot, status in self._pending.items():
            state.status[robot] = status
            state.deactivation_time[robot] = state.time
            state.velocity[robot] = 0.0
        self._pending.clear()

    def _handle_failures(self, failures: list[UserFailure]) -> np.ndarray:
        """Record user-code failures and apply the policy; returns the robots that failed."""
        if not failures:
            return np.zeros(0, dtype=np.int64)
        state = self.state
        failed: list[int] = []
        for failure in failures:
            robots = (np.flatnonzero(state.active).tolist() if failure.robot < 0
                      else [failure.robot])
            detail = f"Exception: {failure.kind}: {failure.message}" + (
                f" ({failure.where})" if failure.where else "")
            for robot in robots:
                self._mark(robot, Status.ERROR, detail, "exception", traceback=failure.traceback)
                failed.append(robot)
        if self.policy == "abort" and self.status == "running":
            self.error = failures[0].describe()
            self.user_exception = failures[0].exception
            self.status = "error"
        return np.array(failed, dtype=np.int64)
