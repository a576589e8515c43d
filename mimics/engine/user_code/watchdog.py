"""Ending a run whose user code does not return before the wall-clock limit.

The engine checks the wall limit between steps; a step that never returns
(``while True: pass``) never gets there. A run with a wall limit has a
:class:`Watchdog`; if user code is still running :data:`GRACE` seconds after
the limit, it is stopped in the simulation's thread:

* Python code gets a :class:`StepTimeout` raised into it (CPython's
  ``PyThreadState_SetAsyncExc``), at the next line it runs, so the traceback
  shows where it was stuck. ``StepTimeout`` is not an ``Exception``: a user's
  ``except Exception`` does not swallow it. It is raised again every
  :data:`RETRY` seconds while the code keeps running (a bare ``except:``), at
  most :data:`TRIES` times. Code stuck inside one long C call (``time.sleep``)
  is stopped when that call returns.
* C and C++ code (``mimics.native``) is cut by a signal to that thread, whose
  handler jumps back to the host code that called it.

The watchdog only interrupts while the simulation is inside user code
(:meth:`Watchdog.enter` and :meth:`Watchdog.leave` bracket it under a lock), so
the engine's own arrays are never left half-updated. Watchdogs exist only in
runs with a wall limit; one thread per process (``mimics-wall-limit``) checks
them every :data:`POLL` seconds and ends :data:`IDLE` seconds after the last run.

The import of a user's file is watched the same way (:func:`watched_load`): an
endless loop at file level ends in a :class:`StepTimeout` naming its line.
"""

from __future__ import annotations

import contextlib
import ctypes
import math
import os
import threading
import time
import weakref
from collections.abc import Callable, Iterator

from mimics.engine.user_code.failure_places import failure_place, user_traceback
from mimics.world.errors import MimicsError

#: Seconds past the wall limit before user code still running is interrupted.
GRACE = 0.5
#: Seconds between interruptions of code that keeps running.
RETRY = 0.5
#: Interruptions before the watchdog gives up (a battery still kills the worker).
TRIES = 20
#: Seconds between the watcher thread's checks.
POLL = 0.1
#: Seconds without an armed watchdog after which the watcher thread ends.
IDLE = 2.0

_set_async = ctypes.PYFUNCTYPE(ctypes.c_int, ctypes.c_ulong, ctypes.py_object)(
    ("PyThreadState_SetAsyncExc", ctypes.pythonapi))
_clear_async = ctypes.PYFUNCTYPE(ctypes.c_int, ctypes.c_ulong, ctypes.c_void_p)(
    ("PyThreadState_SetAsyncExc", ctypes.pythonapi))


class StepTimeout(BaseException):
    """Raised into user code still running past the wall limit.

    ``robot`` is the robot whose call was stopped (-1: the team algorithm) and
    ``entry`` the function called (``"step()"``, ``"mimics_step"``...); the
    controller that called it fills them in.
    """

    robot: int = -1
    entry: str = "step()"


class LoadTimeout(MimicsError):
    """A user's file did not finish importing within its limit (the message names it)."""


@contextlib.contextmanager
def watched_load(limit: float | None) -> Iterator[None]:
    """Run the body (a user file's import) under a :class:`Watchdog` of ``limit`` seconds:
    code still running past it gets :class:`StepTimeout`. ``None``: unwatched."""
    if limit is None or not math.isfinite(limit):
        yield
        return
    started = time.perf_counter()
    watchdog = Watchdog(max(0.0, limit - GRACE), lambda: time.perf_counter() - started,
                        raise_in_thread)
    watchdog.enter()
    try:
        yield
    finally:
        watchdog.leave()
        watchdog.close()


def blame(stop: StepTimeout, robot: int, entry: str) -> None:
    """Say whose call ``stop`` stopped, unless the code that raised it already said."""
    own = vars(stop)
    own.setdefault("robot", robot)
    own.setdefault("entry", entry)


def raise_in_thread(thread_id: int) -> None:
    """Have :class:`StepTimeout` raised in the Python thread ``thread_id``."""
    _set_async(thread_id, StepTimeout)


class Watchdog:
    """Interrupts user code still running when ``elapsed()`` passes ``limit`` + :data:`GRACE`.

    Args:
        limit: the run's wall limit (s).
        elapsed: the run's wall time so far (s), as the engine counts it for the limit.
        interrupt: stops the user code running in the given thread (the
            controller's :meth:`~mimics.engine.user_code.controllers.Controller.interrupt`).
    """

    def __init__(self, limit: float, elapsed: Callable[[], float],
                 interrupt: Callable[[int], None]) -> None:
        self._limit = limit + GRACE
        self._elapsed = elapsed
        self._interrupt = interrupt
        self._lock = threading.Lock()
        self._inside = False
        self._thread_id = threading.get_ident()
        self._fired = False
        self._next = 0.0  # when to interrupt again (time.perf_counter)
        self._tries = 0
        _WATCHER.arm(self)

    def enter(self) -> None:
        """The simulation's thread starts running user code."""
        with self._lock:
            self._inside = True
            self._thread_id = threading.get_ident()

    def leave(self) -> None:
        """The user code returned (or was stopped): no interruption may reach what follows."""
        with self._lock:
            self._inside = False
            if self._fired:  # fired just as the code returned: drop what is still pending
                _clear_async(self._thread_id, None)

    def close(self) -> None:
        """Stop watching (at the end of the run)."""
        _WATCHER.disarm(self)

    def check(self, now: float) -> bool:
        """Interrupt the user code if it runs past its time (between steps the engine's
        own check ends the run); False once the watchdog gives up."""
        if now < self._next or self._elapsed() < self._limit:
            return True
        with self._lock:
            if self._tries >= TRIES:
                return False
            if not self._inside:
                return True
            self._fired = True
            self._tries += 1
            self._next = now + RETRY
            self._interrupt(self._thread_id)
        return True


class _Watcher:
    """One daemon thread per process that checks the armed watchdogs every :data:`POLL`
    seconds. It starts with the first armed watchdog and ends once none has been armed for
    :data:`IDLE` seconds, so a battery's runs share it and nothing stays after them.
    (A thread started and joined per run cost milliseconds a run on a busy machine: the
    new thread, and its end, must be scheduled while the run holds the GIL.)"""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        # weak: a simulation dropped before its end (stepped by hand) is not watched forever
        self._armed: weakref.WeakSet[Watchdog] = weakref.WeakSet()
        self._thread: threading.Thread | None = None
        if hasattr(os, "register_at_fork"):  # a forked child has no watcher thread yet
            os.register_at_fork(after_in_child=self._forget)

    def _forget(self) -> None:
        self._lock = threading.Lock()
        self._armed = weakref.WeakSet()
        self._thread = None

    def arm(self, watchdog: Watchdog) -> None:
        with self._lock:
            self._armed.add(watchdog)
            if self._thread is None:
                self._thread = threading.Thread(target=self._watch, name="mimics-wall-limit",
                                                daemon=True)
                self._thread.start()

    def disarm(self, watchdog: Watchdog) -> None:
        with self._lock:
            self._armed.discard(watchdog)

    def _watch(self) -> None:
        idle = 0.0
        while True:
            time.sleep(POLL)
            with self._lock:
                armed = list(self._armed)
                idle = 0.0 if armed else idle + POLL
                if idle >= IDLE:
                    self._thread = None
                    return
            now = time.perf_counter()
            done = [watchdog for watchdog in armed if not watchdog.check(now)]
            with self._lock:
                for watchdog in done:
                    self._armed.discard(watchdog)


_WATCHER = _Watcher()  # the process's watcher thread (not run state: runs only register)


def describe_timeout(stop: StepTimeout, wall_limit: float, step: int, now: float
                     ) -> tuple[str, str, str]:
    """The run's error, the event's detail and the user's traceback of a stopped call.

    The error names the robot, the step and, for Python code, the file and line
    it was stuck at, then shows that line: ``robot 0: step() did not return within
    the wall limit of 3 s; stopped at step 12 (t=1.2 s), bad.py:5``.
    """
    place = failure_place(stop)
    what = f"{stop.entry} did not return within the wall limit of {wall_limit:g} s"
    who = "the team algorithm" if stop.robot < 0 else f"robot {stop.robot}"
    error = (f"{who}: {what}; stopped at step {step} (t={now:g} s)"
             + (f", {place}" if place else "") + (f"\n    {place.text}" if place and place.text
                                                   else ""))
    detail = f"Exception: StepTimeout: {what}" + (f" ({place})" if place else "")
    return error, detail, user_traceback(stop) if place is not None else ""
