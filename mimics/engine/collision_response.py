"""What a collision does under ``on_collision = "stall"``: the robot stays, stalled.

Stage's habit, which ROS labs rely on: a robot that bumps into a wall or
another robot does not move into it. Here a moving robot whose move this step
makes it touch a wall or a solid robot is put back where it was before the
step (pose, odometer and path length: it did not move), its velocity and
acceleration set to zero; it stays active, and ``state.stalled`` flags it for
the step, for the bridges and for user code (``robot.stalled``). Its control
loops keep the step's update: put back too, a loop's integral would hold the
push that stalled it, and a robot told to back off would push on forever.

Putting one robot back can make another that moved into its old place touch
it, so the moved robots are checked again until none touches anything. Each
round puts back at least one robot whose pose had changed, and a robot put
back stands where it stood before the step, free then: the rounds end. Only a
step with a contact pays for them; a step without one costs a copy of the few
arrays a move changes.

A robot that touches something at a pose it did not move to (robots allowed
to start overlapping) cannot be put back: it is flagged stalled while it
touches. Each stall that was not one the step before is a contact, recorded
by the engine as a ``collision`` event.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from mimics.engine.collision import NONE
from mimics.engine.motion_checks import MotionChecks
from mimics.engine.state import WorldState


class StallOnCollision:
    """The engine's response to collisions when they stall robots (see the module).

    Attributes:
        ever: ``(n,)`` robots stalled at least once in the run (the summary's collisions).
        contacts: ``(robot, other)`` of the stalls that began at the last check: what
            each robot touched first (-1 a wall, else the robot's index).
    """

    def __init__(self, n: int) -> None:
        self._pose = np.zeros((n, 3))
        self._odometry = np.zeros((n, 3))
        self._path_length = np.zeros(n)
        self._remembered = False  # a move since the last check: it can be undone
        self.ever = np.zeros(n, dtype=bool)
        self.contacts: list[tuple[int, int]] = []

    def remember(self, state: WorldState) -> None:
        """Before the robots move: what a move changes and a stall puts back."""
        np.copyto(self._pose, state.pose)
        np.copyto(self._odometry, state.odometry)
        np.copyto(self._path_length, state.path_length)
        self._remembered = True

    def respond(self, state: WorldState, ids: np.ndarray, checks: MotionChecks,
                check_again: Callable[[np.ndarray], MotionChecks]) -> MotionChecks:
        """Put back the robots of ``ids`` whose move made them touch something, until
        none that moved does; set ``state.stalled`` and :attr:`contacts`.

        Args:
            state: the world, robots ``ids`` just moved (or at the start: not moved).
            ids: the robots checked, ascending.
            checks: their check at the poses they moved to.
            check_again: the same check of ``ids`` at the current poses (the robot
                index rebuilt: poses changed within the step).

        Returns:
            The last check: its distances and screen are those of the final poses.
        """
        stalled = state.stalled
        before = stalled.copy() if stalled.any() else None
        stalled[:] = False
        self.contacts = []
        undo, self._remembered = self._remembered, False
        if not checks.touching:
            return checks
        first: dict[int, int] = {}  # what each robot touched first this step
        while True:
            with_whom = checks.with_whom[ids]
            hit = with_whom != NONE
            touching = ids[hit]
            for robot, other in zip(touching.tolist(), with_whom[hit].tolist(), strict=True):
                first.setdefault(robot, other)
            # robots put back stand where they stood: no longer among those that moved
            moved = (touching[np.any(state.pose[touching] != self._pose[touching], axis=1)]
                     if undo else touching[:0])
            if not moved.size:
                break
            self._put_back(state, moved)
            stalled[moved] = True
            checks = check_again(ids)
            if not checks.touching:
                touching = ids[:0]
                break
        stalled[touching] = True  # touching where it stood before the step: stalled there
        began = stalled if before is None else stalled & ~before
        self.contacts = [(robot, first[robot]) for robot in np.flatnonzero(began).tolist()]
        self.ever |= stalled
        return checks

    def clear(self, state: WorldState) -> None:
        """A step without robots to check: nobody is stalled."""
        state.stalled[:] = False
        self.contacts = []
        self._remembered = False

    def _put_back(self, state: WorldState, robots: np.ndarray) -> None:
        """Robots ``robots`` as before the step, standing still."""
        state.pose[robots] = self._pose[robots]
        state.odometry[robots] = self._odometry[robots]
        state.path_length[robots] = self._path_length[robots]
        state.velocity[robots] = 0.0
        state.acceleration[robots] = 0.0
