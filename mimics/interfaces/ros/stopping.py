"""Ending a ROS run cleanly on SIGINT (Ctrl-C) and SIGTERM (what roslaunch sends).

The signal handler only records the request: the run's thread notices it
where it waits (the lockstep inbox, the realtime pace, a pause) within a
fraction of a second, finishes the step under way (robots still waiting for
a command hold their last references), and ends the run at that step
boundary with status ``interrupted``. The summary and records are then
written and the bridge withdraws its topics, services and parameters as
after any run. A second signal while the first is handled raises
:class:`KeyboardInterrupt` at once, for a run that is stuck elsewhere.
"""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from types import FrameType
from typing import Any

from mimics.world.errors import MimicsError

STATUS = "interrupted"
SIGNALS = (signal.SIGINT, signal.SIGTERM)
POLL = 0.05  # seconds between two looks at the request while waiting


class RunInterrupted(MimicsError):
    """A signal came before the run's first step (nothing was recorded)."""

    def __init__(self, signum: int) -> None:
        super().__init__(f"interrupted by {signal.Signals(signum).name} before the run "
                         "started (nothing recorded)")
        self.signum = signum


class StopRequest:
    """Whether (and by which signal) the run was asked to stop."""

    def __init__(self) -> None:
        self.signum: int | None = None

    @property
    def requested(self) -> bool:
        """Whether a stop was asked for."""
        return self.signum is not None

    def ask(self, signum: int = signal.SIGINT) -> None:
        """Ask the run to stop (what the signal handler does)."""
        self.signum = signum

    def _handle(self, signum: int, _frame: FrameType | None) -> None:
        if self.signum is not None:  # a second signal: the user insists
            raise KeyboardInterrupt
        self.signum = signum

    def check(self) -> None:
        """Raise :class:`RunInterrupted` if a stop was asked (before the run starts)."""
        if self.signum is not None:
            raise RunInterrupted(self.signum)

    @contextmanager
    def handling_signals(self) -> Iterator[StopRequest]:
        """Handle SIGINT and SIGTERM while the block runs (main thread only; elsewhere
        Python cannot install handlers and the signals keep their handlers)."""
        if threading.current_thread() is not threading.main_thread():
            yield self
            return
        previous: dict[int, Any] = {signum: signal.getsignal(signum) for signum in SIGNALS}
        for signum in SIGNALS:
            signal.signal(signum, self._handle)
        try:
            yield self
        finally:
            for signum, handler in previous.items():
                signal.signal(signum, handler)


def exit_status(signum: int) -> int:
    """The shell's status for a process ended by ``signum``: 128 + its number (130, 143)."""
    return 128 + int(signum)
