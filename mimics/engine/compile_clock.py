"""How long this process has spent compiling kernels, so that no run counts it as its own.

Numba compiles a kernel at its first call when its on-disk cache lacks it,
which on a fresh install happens inside a run's first steps (or in the
processes the CLI starts to compile ahead, which the first scan waits for).
That time says nothing of the simulation's speed: the run's wall time, its
speed and its user code's time leave it out, and the CLI reports it on a line
of its own. Two sources add to the clock:

- every compile in this process (Numba's ``numba:compile`` events; a kernel
  compiled inside another's compile counts once);
- waits for kernels another process compiles (:func:`add_wait`).

Loading a kernel from the cache is not a compile and is not counted.
"""

from __future__ import annotations

import threading
import time
from typing import Any

from numba.core import event

_lock = threading.Lock()
_total = [0.0]
_open = threading.local()  # per thread: (depth of nested compiles, start of the outermost)


class _Listener(event.Listener):  # type: ignore[misc]
    def on_start(self, ev: Any) -> None:
        depth = getattr(_open, "depth", 0)
        if depth == 0:
            _open.began = time.perf_counter()
        _open.depth = depth + 1

    def on_end(self, ev: Any) -> None:
        depth = getattr(_open, "depth", 0)
        if depth == 0:  # a compile begun before this listener was registered
            return
        _open.depth = depth - 1
        if depth == 1:
            add_wait(time.perf_counter() - _open.began)


def add_wait(seconds: float) -> None:
    """Count ``seconds`` spent waiting for kernels to be compiled (here or elsewhere)."""
    with _lock:
        _total[0] += seconds


def compile_seconds() -> float:
    """Seconds this process has spent compiling or waiting for compiles so far."""
    return _total[0]


event.register("numba:compile", _Listener())
