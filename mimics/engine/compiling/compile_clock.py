"""How long this process has spent compiling kernels, so that no run counts it as its own.

Numba compiles a kernel at its first call when its on-disk cache lacks it,
which on a fresh install happens inside a run's first steps (or in the
processes the CLI starts to compile ahead, which the first scan waits for).
That time says nothing of the simulation's speed: the run's wall time, its
speed and its user code's time leave it out, and the CLI reports it on a line
of its own. Two sources add to the clock:

- every compile in this process (Numba's ``numba:compile`` events; a kernel
  compiled inside another's compile counts once);
- waits for kernels another process compiles (:func:`waiting`).

A compile or wait under way counts as far as it has gone, so that a reader in
another thread (the wall-limit watchdog) never takes a long first compile for
user code that does not return.

Loading a kernel from the cache is not a compile and is not counted.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

from numba.core import event

_lock = threading.Lock()
_total = [0.0]
_under_way: dict[int, float] = {}  # thread -> start of its outermost compile or wait
_depth = threading.local()  # per thread: nested compiles and waits count once


def _enter() -> None:
    depth = getattr(_depth, "n", 0)
    if depth == 0:
        with _lock:
            _under_way[threading.get_ident()] = time.perf_counter()
    _depth.n = depth + 1


def _leave() -> None:
    depth = getattr(_depth, "n", 0)
    if depth == 0:  # a compile begun before this listener was registered
        return
    _depth.n = depth - 1
    if depth == 1:
        with _lock:
            _total[0] += time.perf_counter() - _under_way.pop(threading.get_ident())


class _Listener(event.Listener):  # type: ignore[misc]
    def on_start(self, ev: Any) -> None:
        _enter()

    def on_end(self, ev: Any) -> None:
        _leave()


@contextmanager
def waiting() -> Iterator[None]:
    """Count the time inside as a wait for kernels (compiled here or elsewhere)."""
    _enter()
    try:
        yield
    finally:
        _leave()


def compile_seconds() -> float:
    """Seconds this process has spent compiling or waiting for compiles so far, those
    under way included."""
    now = time.perf_counter()
    with _lock:
        return _total[0] + sum(now - began for began in _under_way.values())


event.register("numba:compile", _Listener())
