"""Play, pause, step and stop a simulation that runs in a background thread.

:class:`SimulationStepper` owns one :class:`~mimics.engine.simulation.Simulation`
and steps it in its own thread, so that whoever holds the controls (a
notebook widget, the workbench) stays responsive. While playing it keeps the
simulated time at ``speed`` simulated seconds per wall second (``math.inf``:
as fast as the machine goes), and calls ``on_frame(sim)`` from its thread at
most ``fps`` times per wall second, once after every single step taken while
paused, and once at the end. Stop ends the run where it is, at the step
boundary it comes to (no step more), with the status ``"stopped"``
(``Simulation.end``: observers see ``on_end`` as for any run, and the end joins
the scenario's edits, so the run's record re-runs to the same end).

>>> from mimics.records.runner import prepare
>>> sim = prepare("line", "go_to_goal", robots=2, time=1.0, seed=1)
>>> seen = []
>>> stepper = SimulationStepper(sim, lambda s: seen.append(s.state.step), speed=math.inf)
>>> stepper.step(); stepper.step(); _ = stepper.wait_paused()
>>> seen, stepper.state
([0, 1, 2], 'paused')
>>> stepper.play(); stepper.wait_ended(timeout=60)
True
>>> sim.status, seen[-1] == sim.state.step
('time_limit', True)

Edits of the running world (``mimics.engine.edits``) go through the stepper's
thread: :meth:`SimulationStepper.edit` waits until the edit is applied at the
next step boundary (at once when paused) and returns it as plain data, or
raises the one-line refusal:

>>> sim = prepare("line", "go_to_goal", robots=2, time=1.0, seed=1)
>>> stepper = SimulationStepper(sim, lambda s: None, speed=math.inf)
>>> stepper.edit({"kind": "move_robot", "robot": 0, "x": 1.0, "y": 1.0, "yaw": 0.5})
{'step': 0, 'kind': 'move_robot', 'robot': 0, 'x': 1.0, 'y': 1.0, 'yaw': 0.5, 'time': 0.0, \
'detail': 'move robot 0 to (1, 1, yaw 0.5)'}
>>> stepper.edit({"kind": "remove_robot", "robot": 7})
Traceback (most recent call last):
...
mimics.world.edits.EditError: edit.robot: no robot 7 (the run has 2: 0 to 1)
>>> stepper.close()
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Mapping
from typing import Any

from mimics.world.errors import MimicsError

STATES = ("paused", "playing", "ended")


class _EditRequest:
    """An edit (or a read: a callable of the simulation) waiting for the stepper's thread,
    and what became of it."""

    def __init__(self, edit: Mapping[str, Any] | Callable[[Any], Any]) -> None:
        self.edit: dict[str, Any] | Callable[[Any], Any] = (
            edit if callable(edit) else dict(edit))
        self.done = threading.Event()
        self.applied: Any = None
        self.refusal: BaseException | None = None
        self.taken = False  # the stepper's thread is applying it
        self.cancelled = False  # its caller stopped waiting before that: never apply it


class SimulationStepper:
    """Controls over a simulation stepping in a background thread.

    Args:
        sim: a simulation that has not run yet (it may have observers).
        on_frame: called with the simulation when a frame is due (from the
            stepper's thread; the simulation does not change during the call).
        speed: simulated seconds per wall second while playing (``math.inf``: no pacing).
        fps: frames per wall second at most while playing.

    Attributes:
        state: ``"paused"``, ``"playing"`` or ``"ended"``.
        error: the exception that ended the thread, if any (also re-raised by
            ``wait_ended``).
    """

    def __init__(self, sim: Any, on_frame: Callable[[Any], Any], *, speed: float = 1.0,
                 fps: float = 10.0) -> None:
        if sim.state.step != 0 or sim.status != "running":
            raise MimicsError("stepper: the simulation has already run; give it a new one")
        if not fps > 0:
            raise MimicsError(f"stepper: fps must be positive, got {fps!r}")
        self.sim = sim
        self.on_frame = on_frame
        self.fps = float(fps)
        self.speed = check_speed(speed)
        self.state = "paused"
        self.error: BaseException | None = None
        self._wake = threading.Condition()
        self._steps_asked = 0  # single steps asked while paused
        self._ending: str | None = None  # the status a Stop asked the run to end with
        self._closed = False
        self._edits: list[_EditRequest] = []  # asked, not yet applied
        self._thread = threading.Thread(target=self._loop, name="mimics-stepper", daemon=True)
        self._thread.start()

    # -- controls (any thread) ---------------------------------------------------

    def play(self) -> None:
        """Run on at ``speed``."""
        self._set("playing")

    def pause(self) -> None:
        """Stop stepping after the current step; the last frame stays."""
        self._set("paused")

    def step(self) -> None:
        """Pause (if playing), then advance exactly one step and draw it."""
        with self._wake:
            if self.state == "ended":
                return
            self.state = "paused"
            self._steps_asked += 1
            self._wake.notify_all()

    def stop(self, status: str = "stopped") -> None:
        """End the run at the step boundary it comes to, without another step, with
        ``status`` (``"stopped"``; ``"wall_limit"`` for a wall limit that passed while
        paused); the first Stop's status holds."""
        with self._wake:
            if self._ending is None:
                self._ending = status
            self._wake.notify_all()

    def set_speed(self, speed: float) -> None:
        """Change the simulated seconds per wall second (``math.inf``: no pacing)."""
        self.speed = check_speed(speed)
        with self._wake:
            self._wake.notify_all()

    def edit(self, edit: Mapping[str, Any], timeout: float = 30.0) -> dict[str, Any]:
        """Apply an edit of the world (``mimics.world.edits``: ``{"kind": "add_wall",
        "segment": [x1, y1, x2, y2]}``...) at the next step boundary, at once when
        paused; waits for it (any thread) and returns it as applied: its fields, the
        ``step`` and ``time`` it was applied at and a ``detail`` line.

        Raises:
            MimicsError: one line: the edit is malformed or refused, the run has ended,
                or the stepper's thread did not take it within ``timeout`` seconds.
        """
        applied = self._at_boundary(_EditRequest(edit), timeout)
        assert applied is not None
        return applied

    def between_steps(self, read: Callable[[Any], Any], timeout: float = 30.0) -> Any:
        """``read(sim)``, called in the stepper's thread at the next step boundary (at
        once when paused) while the simulation holds still: for reads that must not race
        a step, such as tracing the ranger's lazy scan. Waits for it (any thread).

        Raises:
            MimicsError: one line: the run has ended, or the boundary did not come
                within ``timeout`` seconds; or what ``read`` raised.
        """
        return self._at_boundary(_EditRequest(read), timeout)

    def _at_boundary(self, request: _EditRequest, timeout: float) -> Any:
        """Queue ``request`` for the stepper's thread; its result (refusals raised)."""
        what = "edit" if isinstance(request.edit, dict) else "read"
        with self._wake:
            if self.state == "ended" or self._closed:
                raise MimicsError(f"{what}: the run has ended; nothing to {what}")
            self._edits.append(request)
            self._wake.notify_all()
        if not request.done.wait(timeout):
            with self._wake:
                if not request.taken:
                    request.cancelled = True
                    raise MimicsError(f"{what}: not done within {timeout:g} s (the "
                                      "simulation is busy in a step)")
            request.done.wait()  # being applied now: a moment
        if request.refusal is not None:
            raise request.refusal
        return request.applied

    def close(self) -> None:
        """Leave the thread (the run is left where it is, not ended)."""
        with self._wake:
            self._closed = True
            self._wake.notify_all()
        self._thread.join(5.0)

    def wait_paused(self, timeout: float = 30.0) -> bool:
        """Wait until no single step is pending; True when so."""
        deadline = time.monotonic() + timeout
        with self._wake:
            while self._steps_asked and self.state != "ended":
                if not self._wake.wait(max(0.0, deadline - time.monotonic())):
                    return False
        return True

    def wait_ended(self, timeout: float | None = None) -> bool:
        """Wait for the run to end; True when it has. Re-raises the thread's exception."""
        self._thread.join(timeout)
        if self.error is not None:
            raise self.error
        return self.state == "ended"

    def _set(self, state: str) -> None:
        with self._wake:
            if self.state != "ended":
                self.state = state
                self._wake.notify_all()

    # -- the thread -----------------------------------------------------------------

    def _loop(self) -> None:
        sim = self.sim
        try:
            sim.start()
            # the gaps between the engine's calls (pacing, pauses, frames) are the run's
            # waits, not its wall time (Simulation.waited)
            engine_left = time.perf_counter()
            self.on_frame(sim)
            anchor: tuple[float, float] | None = None  # (wall, sim time) when pacing began
            last_frame = 0.0
            while sim.status == "running":
                if self._apply_edits(sim):
                    continue  # the edits may have ended the run, or more came
                with self._wake:
                    while (self.state == "paused" and not self._steps_asked
                           and self._ending is None and not self._closed
                           and not self._edits):
                        anchor = None
                        self._wake.wait()
                    if self._closed:
                        return
                    if self._edits:
                        continue
                    ending = self._ending
                    single = self.state == "paused" and self._steps_asked > 0
                    speed = self.speed
                sim.waited += time.perf_counter() - engine_left
                if ending is not None:
                    sim.end(ending)  # here, between steps: the end is recorded in its edits
                    break
                sim.step()
                engine_left = time.perf_counter()
                now = time.monotonic()
                if single:
                    self.on_frame(sim)
                    last_frame = now
                    with self._wake:  # after the frame: wait_paused() then sees it drawn
                        self._steps_asked -= 1
                        self._wake.notify_all()
                    continue
                if now - last_frame >= 1.0 / self.fps and sim.status == "running":
                    self.on_frame(sim)
                    last_frame = time.monotonic()
                if math.isfinite(speed):
                    if anchor is None or anchor[1] > sim.state.time:
                        anchor = (now, sim.state.time)
                    ahead = anchor[0] + (sim.state.time - anchor[1]) / speed - time.monotonic()
                    if ahead > 0:
                        with self._wake:  # a control wakes the pause early
                            self._wake.wait(ahead)
                        if self.speed != speed:
                            anchor = None
            self.on_frame(sim)
        except BaseException as exc:  # kept for wait_ended; the thread must not die silently
            self.error = exc
        finally:
            with self._wake:
                self.state = "ended"
                self._steps_asked = 0
                left, self._edits = self._edits, []
                self._wake.notify_all()
            for request in left:
                request.refusal = MimicsError("edit: the run has ended; nothing to edit")
                request.done.set()

    def _apply_edits(self, sim: Any) -> bool:
        """Apply the edits asked for (in the stepper's thread, between steps); True if
        there were any (a frame then shows them when paused)."""
        with self._wake:
            requests, self._edits = self._edits, []
        if not requests:
            return False
        edited = False
        for request in requests:
            with self._wake:
                if request.cancelled:
                    continue
                request.taken = True
            try:
                if callable(request.edit):
                    request.applied = request.edit(sim)
                else:
                    edited = True
                    request.applied = sim.edit(request.edit).to_dict()
            except MimicsError as refusal:
                request.refusal = refusal
            except BaseException as exc:  # a bug: the caller hears of it, the thread ends
                request.refusal = exc
                if not callable(request.edit) or not isinstance(exc, Exception):
                    raise  # (a read that failed changed nothing: the run goes on)
            finally:
                request.done.set()
        if edited and (self.state == "paused" or sim.status != "running"):
            self.on_frame(sim)
        return True


def check_speed(speed: float) -> float:
    """A positive speed (simulated seconds per wall second; ``math.inf`` allowed).

    Raises:
        MimicsError: naming the value.
    """
    if isinstance(speed, bool) or not isinstance(speed, int | float) or not speed > 0:
        raise MimicsError(f"speed: expected a positive number of simulated seconds per "
                          f"second (or math.inf), got {speed!r}")
    return float(speed)
