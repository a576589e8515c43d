"""The meaning of the pause, resume, step and reset services, free of any ROS library.

:class:`RunControl` is the state the services (ROS 1's
:mod:`~mimics.interfaces.ros.services`, ROS 2's
:mod:`mimics.interfaces.ros2.services`) and the run's thread share; the
bridge core calls :meth:`RunControl.gate` before publishing each step. What
each service does is told in :mod:`~mimics.interfaces.ros.services`.
"""

from __future__ import annotations

import threading
import time as wall
from pathlib import Path

from mimics.interfaces.ros.stopping import POLL, StopRequest

SERVICES = ("pause", "resume", "step", "reset")


class RunControl:
    """Pause, single steps and reset requests, shared between ROS's threads and the run.

    Args:
        answer_within: seconds a service waits for the run to act on it
            (a run waiting for late commands holds only once they come).
    """

    def __init__(self, answer_within: float) -> None:
        self.answer_within = answer_within
        self._changed = threading.Condition()
        self._paused = False
        self._steps = 0  # paused: steps allowed to be published
        self._reset = False
        self._held_at: tuple[int, float] | None = None  # (step, time) last published, held
        self._published: tuple[int, float] = (-1, 0.0)
        self._ended = False
        self._restarts = 0  # runs started by a reset
        self.folder: Path | None = None  # the current run's folder
        self.stop_request: StopRequest | None = None  # a signal ends a paused run too

    # -- the run's side --------------------------------------------------------

    def gate(self) -> tuple[bool, float]:
        """Before a step is published: wait while paused.

        Returns (publish, seconds held): ``publish`` is False when a reset
        was asked (the step is not published; the run ends).
        """
        with self._changed:
            start = wall.monotonic()
            while self._paused and self._steps == 0 and not self._reset:
                if self.stop_request is not None and self.stop_request.requested:
                    break
                self._held_at = self._published
                self._changed.notify_all()
                self._changed.wait(POLL)  # bounded: a signal handler cannot notify
            self._held_at = None
            if self._steps > 0:
                self._steps -= 1
            return not self._reset, wall.monotonic() - start

    def published(self, step: int, seconds: float) -> None:
        """A step has been published."""
        with self._changed:
            self._published = (step, seconds)
            self._changed.notify_all()

    def run_started(self, folder: Path) -> None:
        """A run (the first, or one after a reset) is about to start in ``folder``."""
        with self._changed:
            self.folder = folder
            self._ended = self._reset = False
            self._published = (-1, 0.0)
            self._changed.notify_all()

    def run_ended(self) -> None:
        """The run has ended (any service waiting on it is answered)."""
        with self._changed:
            self._ended = True
            self._changed.notify_all()

    def reset_asked(self, _sim: object = None) -> bool:
        """Whether a reset ends the run (the simulation's ``stop_when``)."""
        return self._reset

    def next_reset_folder(self, first: Path) -> Path:
        """The folder of the next run after a reset: ``FIRST-reset-K``, never one taken."""
        while True:
            self._restarts += 1
            folder = first.with_name(f"{first.name}-reset-{self._restarts}")
            if not folder.exists():
                return folder

    # -- the services' side -----------------------------------------------------

    def pause(self) -> tuple[bool, str]:
        """Pause; answers once the run holds (or says it will hold before its next step)."""
        with self._changed:
            if self._ended and not self._reset:
                return False, "the run has ended"
            self._paused, self._steps = True, 0
            self._changed.notify_all()
            if not self._changed.wait_for(lambda: self._held_at is not None or self._ended,
                                          self.answer_within):
                return True, "pausing: the run holds before publishing its next step"
            if self._held_at is None:
                return False, "the run has ended"
            return True, _held_text("paused", *self._held_at)

    def resume(self) -> tuple[bool, str]:
        """Let the run go on."""
        with self._changed:
            was = self._paused
            self._paused, self._steps = False, 0
            self._changed.notify_all()
        return True, "resumed" if was else "was not paused"

    def step(self) -> tuple[bool, str]:
        """Paused: publish one more step, then hold; answers with that step."""
        with self._changed:
            if not self._paused:
                return False, "not paused: call /mimics/pause first"
            if self._ended:
                return False, "the run has ended"
            before = self._published[0]
            self._steps += 1
            self._changed.notify_all()
            done = self._changed.wait_for(
                lambda: self._ended or (self._held_at is not None and self._steps == 0
                                        and self._published[0] > before),
                self.answer_within)
            step, seconds = self._published
            if step <= before:
                return False, "the run has ended" if self._ended else "the step has not come yet"
            return True, _held_text("stepped" if done else "stepping", step, seconds)

    def reset(self) -> tuple[bool, str]:
        """End the run and start it again; answers once the new run has published step 0."""
        with self._changed:
            if self._ended:
                return False, "the run has ended"
            old = self.folder
            self._reset = True
            self._changed.notify_all()
            started = self._changed.wait_for(
                lambda: self.folder != old and self._published[0] >= 0, self.answer_within)
            if not started:
                return True, "resetting: the run ends at its next step and starts again"
            return True, f"reset: the run started again from t=0 in {self.folder}"


def _held_text(verb: str, step: int, seconds: float) -> str:
    return f"{verb} at step {step} (t={seconds:g} s published last)"
