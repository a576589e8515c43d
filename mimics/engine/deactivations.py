"""How robots leave a run: arrivals, escapes, collisions, stalls and failures.

A part of :class:`~mimics.engine.simulation.Simulation` kept on its own: a
deactivation is recorded during the step (an event, the robot's system
message) and takes effect at the step's end, so that every robot of a step
sees the same world. Under ``on_collision = "stall"`` a collision deactivates
no one: the robot is put back (:mod:`~mimics.engine.collision_response`) and
the contact recorded as a ``collision`` event.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.motion_checks import MotionChecks, check_moved
from mimics.engine.outcome import Event
from mimics.engine.state import Status
from mimics.engine.user_code import UserFailure

if TYPE_CHECKING:
    from mimics.engine.collision_response import StallOnCollision
    from mimics.engine.robot_index import RobotIndex
    from mimics.engine.spatial_index import SegmentGrid
    from mimics.engine.stall import StallDetector
    from mimics.engine.state import TypeArrays, WorldState
    from mimics.world.scenario import Scenario


class RobotDeactivations:
    """The Simulation's bookkeeping of robots leaving the run (a mixin of its state)."""

    state: WorldState
    types: TypeArrays
    scenario: Scenario
    events: list[Event]
    policy: str
    status: str
    error: str
    wall_grid: SegmentGrid
    _robot_index: Callable[[], RobotIndex]
    _grid_key: tuple[int, bytes] | None
    _pending: dict[int, Status]
    _stalls: StallDetector
    _stall_on_collision: StallOnCollision | None
    _ever_deadlocked: np.ndarray
    _ever_livelocked: np.ndarray
    #: the exception of the failure that ended the run under "abort" (None: none)
    user_exception: BaseException | None = None

    def _check_moved(self, ids: np.ndarray) -> tuple[np.ndarray, bool]:
        """Mark (``on_collision = "stall"``: put back) robots ``ids`` that touch a wall or
        a solid robot; returns every robot's goal distance and whether none of ``ids``
        left the map or came within the goal tolerance."""
        stall = self._stall_on_collision
        if ids.size == 0:
            if stall is not None:
                stall.clear(self.state)
            return self.state.goal_distance(), True
        checks = self._checks(ids)
        if stall is not None:
            checks = stall.respond(self.state, ids, checks,
                                   lambda again: self._checks(again, rebuild=True))
            self._record_contacts(stall.contacts)
        elif checks.touching:
            for i in (checks.with_whom != -2).nonzero()[0].tolist():
                other = int(checks.with_whom[i])
                self.state.collided_with[i] = other
                self._mark(i, Status.COLLIDED, f"Collision with {_touched(other)}", "collision",
                           other=other)
        return checks.distance, checks.quiet

    def _checks(self, ids: np.ndarray, rebuild: bool = False) -> MotionChecks:
        """The collisions, goal distances and screen of robots ``ids`` (``motion_checks``);
        ``rebuild``: robots were put back within the step, the robot index is made again."""
        if rebuild:
            self._grid_key = None
        types, scenario = self.types, self.scenario
        return check_moved(self._robot_index(), self.state.pose, types.half_length,
                           types.half_width, ids, self.wall_grid, self.state.goal,
                           scenario.map.bounds, scenario.settings.goal_tolerance)

    def _record_contacts(self, contacts: list[tuple[int, int]]) -> None:
        """A ``collision`` event per stall that began (no status change); ``collided_with``
        keeps the first thing each robot ever touched."""
        for robot, other in contacts:
            if self.state.collided_with[robot] == -2:
                self.state.collided_with[robot] = other
            self._event(robot, "collision", f"Collision with {_touched(other)} (stalled)",
                        other=other)

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


def _touched(other: int) -> str:
    """What a robot touched, as events name it: ``wall`` (-1) or ``robot J``."""
    return "wall" if other == -1 else f"robot {other}"

