"""Handing commands from ROS's threads to the simulation's step.

ROS delivers messages on its own threads; the simulation asks for one
command per active robot and step. Two ways to match them:

* **lockstep**: before the observations of step ``k`` are published, the
  bridge calls :meth:`Inbox.expect`; the first command that arrives for a
  robot after that answers step ``k`` (a stamped ``cmd`` must carry step
  ``k``'s stamp, else it is dropped as stale). :meth:`Inbox.take` waits for
  that answer until the step's deadline: one deadline for the whole step,
  set by :meth:`Inbox.expect`, so a node that dies costs one time-out, not
  one per robot, and the time-out names every robot still waiting. The
  answer depends only on what the controller computed from step ``k``'s
  observations, never on timing, so a run is as deterministic as the
  controller. With a ``grace``, a robot whose node has sent a command
  within the time-out but not for this step holds its last reference once
  the grace has passed (the node skipped the step): the world goes on.
* **realtime**: :meth:`Inbox.take` returns the latest command received;
  :meth:`Inbox.sim_silence` says how long ago (simulated time, as stage_ros
  counts it) the last one came, for the command watchdog.

A malformed message is never used: in lockstep it answers the step with
"hold the last reference", in realtime it is dropped; either way its
problem is returned by the next :meth:`Inbox.take` to be logged.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Literal

from mimics.interfaces.ros.stopping import POLL, StopRequest


@dataclass(frozen=True)
class Command:
    """One command received from ROS for one robot.

    ``kind`` is ``"reference"`` (``first`` = speed reference in m/s,
    ``second`` = absolute heading reference in rad) or ``"twist"`` (``first``
    = speed in m/s, ``second`` = turn rate in rad/s). ``step`` is the step it
    answers when the message was stamped, else None.
    """

    kind: Literal["reference", "twist"]
    first: float
    second: float
    step: int | None = None


HOLD = Command("reference", float("nan"), float("nan"))  # "keep the last reference"


class LockstepTimeout(RuntimeError):
    """No command for a robot's step arrived within the time-out.

    ``robots`` are all the robots still waiting when the step's deadline passed.
    """

    def __init__(self, message: str, robots: tuple[int, ...] = ()) -> None:
        super().__init__(message)
        self.robots = robots


class Inbox:
    """The latest command of each robot, and in lockstep the answer to each step.

    Args:
        robots: how many robots.
        lockstep: match one command to each step (see the module's docstring).
    """

    def __init__(self, robots: int, lockstep: bool, timeout: float = 10.0,
                 stop: StopRequest | None = None, grace: float | None = None) -> None:
        self.lockstep = lockstep
        self.timeout = timeout
        self.grace = grace  # lockstep: hold a live node's robot after this (None: strict)
        self._grace_end = float("inf")
        self.stop_request = stop  # a signal asked the run to end: stop waiting
        self._deadline = float("inf")  # lockstep: when the awaited step's time-out ends
        self._received = [float("-inf")] * robots  # wall time of each robot's last command
        self.now = 0.0  # simulated time of the last step published (the bridge sets it)
        self._received_sim = [float("-inf")] * robots  # ... and its simulated time
        self._ready = threading.Condition()
        self._awaited = [-1] * robots  # lockstep: the step each robot must answer, -1: none
        self._answer: list[Command | None] = [None] * robots
        self._latest: list[Command | None] = [None] * robots
        self._notes: list[list[str]] = [[] for _ in range(robots)]

    def expect(self, step: int, robots: Iterable[int]) -> None:
        """Lockstep: from now on, the next command of each of ``robots`` answers ``step``.

        Starts the step's deadline: every answer must come within
        ``timeout`` seconds from now.
        """
        with self._ready:
            now = time.monotonic()
            self._deadline = now + self.timeout
            self._grace_end = now + self.grace if self.grace is not None else float("inf")
            for robot in robots:
                self._awaited[robot] = step
                self._answer[robot] = None

    def deliver(self, robot: int, command: Command) -> None:
        """A command received from ROS (any thread)."""
        with self._ready:
            if not 0 <= robot < len(self._latest):
                return
            self._received[robot] = time.monotonic()
            self._received_sim[robot] = self.now
            if not self.lockstep:
                self._latest[robot] = command
                return
            awaited = self._awaited[robot]
            if awaited < 0:
                return  # the robot has stopped, or the run has not started: nothing asked
            if command.step is not None and command.step != awaited:
                self._notes[robot].append(f"dropped a cmd stamped for step {command.step} "
                                          f"while waiting for step {awaited}")
                return
            if self._answer[robot] is not None:
                self._notes[robot].append(f"dropped a second command for step {awaited} "
                                          "(lockstep takes the first)")
                return
            self._answer[robot] = command
            self._ready.notify_all()

    def reject(self, robot: int, problem: str) -> None:
        """A malformed message: noted; in lockstep it answers the step with :data:`HOLD`."""
        with self._ready:
            if not 0 <= robot < len(self._latest):
                return
            self._received[robot] = time.monotonic()  # the node is alive, if confused
            self._received_sim[robot] = self.now
            self._notes[robot].append(f"{problem}; holding the last reference")
            if self.lockstep and self._awaited[robot] >= 0 and self._answer[robot] is None:
                self._answer[robot] = HOLD
                self._ready.notify_all()

    def take(self, robot: int, step: int) -> tuple[Command | None, list[str]]:
        """The command for ``robot`` at ``step`` (None: none yet) and the notes since last time.

        Raises:
            LockstepTimeout: in lockstep, when the step's deadline passed
                without an answer; it names every robot still waiting.
        """
        with self._ready:
            if self.lockstep:
                while self._answer[robot] is None or self._awaited[robot] != step:
                    if self.stop_request is not None and self.stop_request.requested:
                        self._answer[robot] = HOLD  # the run ends after this step
                        break
                    now = time.monotonic()
                    if now >= self._grace_end and now - self._received[robot] <= self.timeout:
                        # its node is alive but skipped this step: the robot holds its
                        # references instead of stalling the world
                        self._notes[robot].append(
                            f"no command within the grace ({self.grace:g} s, --grace); "
                            "holding the last reference")
                        self._answer[robot] = HOLD
                        break
                    left = self._deadline - now
                    if left <= 0:
                        waiting = tuple(i for i, awaited in enumerate(self._awaited)
                                        if awaited == step and self._answer[i] is None)
                        raise LockstepTimeout(f"robot {robot}", waiting or (robot,))
                    # bounded: a signal handler only sets a flag, it cannot notify us
                    self._ready.wait(min(left, POLL, max(self._grace_end - now, 0.001)))
                command = self._answer[robot]
                self._awaited[robot] = -1  # later commands until the next expect are surplus
            else:
                command = self._latest[robot]
            notes, self._notes[robot] = _merged(self._notes[robot]), []
        return command, notes

    def silence(self, robot: int) -> float:
        """Wall seconds since the robot's last message (``inf``: none yet)."""
        with self._ready:
            return time.monotonic() - self._received[robot]

    def sim_silence(self, robot: int, seconds: float) -> float:
        """Simulated seconds from the robot's last message to ``seconds`` (``inf``: none
        yet): a paused run's clock stands still, and so does this."""
        with self._ready:
            return seconds - self._received_sim[robot]

    def stop(self) -> None:
        """Nothing is awaited any more (the run has ended)."""
        with self._ready:
            self._awaited = [-1] * len(self._awaited)


def _merged(notes: list[str]) -> list[str]:
    """The notes in order, a note repeated since the last step written once with its count."""
    counts: dict[str, int] = {}
    for note in notes:
        counts[note] = counts.get(note, 0) + 1
    return [note if count == 1 else f"{note} ({count} times)" for note, count in counts.items()]
