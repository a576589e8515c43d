"""Helper threads that share a compiled kernel's chunks with the calling thread.

A kernel call of a fraction of a millisecond (a Cave scan: about 0.45 ms on
one thread) cannot afford a thread pool's hand-over: waking a sleeping
thread and waiting on a future cost 70 us here, a third of what a second
core saves. So the helpers are woken and waited for without the kernel
(futex) and without the GIL:

- Each helper spins (x86 ``pause``, and ``sched_yield`` now and then so a
  busy machine's other threads get the core) in a ``nogil`` kernel until
  the call counter in ``control`` changes, for about ``SPIN_SECONDS``;
  then it sleeps on a condition, and the next call wakes it.
- The calling thread bumps the counter from inside its own ``nogil`` kernel
  call (the GIL is free by then, so a helper that sees it can take the GIL
  at once), takes chunks from a counter shared by the call (``share``,
  atomic adds), closes the call when none is left and waits only for the
  helpers that joined before the close. A helper that wakes late finds the
  call closed and does nothing; nobody waits for a helper that never came.
- A helper reports a finished call from inside its next ``nogil`` wait, so
  the caller, woken by that report, never finds the GIL taken.

Which thread computes which chunk changes from call to call; a kernel whose
chunks depend only on their own inputs gives the same bits whatever the
split (the ray kernel's rows do: ``tests/engine/test_threads.py``).

A kernel run this way takes ``(..., control, share, lead)`` as its last
arguments: it calls :func:`open_call` first when ``lead``, takes chunks
with :func:`next_chunk`, and calls :func:`close_call` last when ``lead``.
"""

from __future__ import annotations

import atexit
import os
import platform
import sys
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

# slots of the arrays below, one cache line (8 int64) apart so that threads writing
# different slots do not share a line
CALLS = 0  # control: calls posted so far
# share: next chunk, helpers joined, helpers finished, a helper's kernel raised
NEXT, JOINED, FINISHED, FAILED = 0, 8, 16, 24
CLOSED = 1 << 40  # added to JOINED by the caller when it has no chunk left
SHARE_SLOTS = 32
SPIN_SECONDS = 0.001  # how long an idle helper spins before it sleeps
_PAUSES_PER_YIELD = 64

_X86 = platform.machine().lower() in ("x86_64", "amd64", "i386", "i686")
_YIELDS = sys.platform != "win32"  # sched_yield is POSIX


def _slot(context: Any, builder: Any, array_type: Any, array: Any, index: Any) -> Any:
    view = context.make_array(array_type)(context, builder, array)
    return cgutils.get_item_pointer(context, builder, array_type, view, [index])


@intrinsic
def atomic_load(typingctx: Any, array: Any, index: Any) -> Any:
    """``array[index]`` read atomically (int64 array): never kept in a register."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        slot = _slot(context, builder, signature.args[0], args[0], args[1])
        return builder.load_atomic(slot, "seq_cst", 8)
    return types.int64(array, index), codegen


@intrinsic
def atomic_add(typingctx: Any, array: Any, index: Any, value: Any) -> Any:
    """Add ``value`` to ``array[index]`` atomically (int64 array); returns the old value."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        slot = _slot(context, builder, signature.args[0], args[0], args[1])
        return builder.atomic_rmw("add", slot, args[2], "seq_cst")
    return types.int64(array, index, types.int64), codegen


@intrinsic
def _relax(typingctx: Any) -> Any:
    """A spin loop's pause (x86 ``pause``: lets the sibling hyperthread run; else nothing)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        if _X86:
            pause = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(ir.VoidType(), []), "llvm.x86.sse2.pause")
            builder.call(pause, [])
        return context.get_dummy_value()
    return types.void(), codegen


@intrinsic
def _yield_core(typingctx: Any) -> Any:
    """``sched_yield()``: another runnable thread on this core goes first (POSIX only)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        if _YIELDS:
            call = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(ir.IntType(32), []), "sched_yield")
            builder.call(call, [])
        return context.get_dummy_value()
    return types.void(), codegen


@njit(cache=True, nogil=True, inline="always")
def open_call(control: np.ndarray) -> None:
    """The caller's first act inside its kernel: wake the spinning helpers."""
    atomic_add(control, CALLS, 1)


@njit(cache=True, nogil=True, inline="always")
def next_chunk(share: np.ndarray) -> int:
    """The next chunk of this call (chunks past the last mean: nothing left)."""
    return atomic_add(share, NEXT, 1)


@njit(cache=True, nogil=True, inline="always")
def close_call(share: np.ndarray) -> None:
    """The caller's last act: no helper joins from now on; wait for those who did."""
    joined = atomic_add(share, JOINED, CLOSED)
    while atomic_load(share, FINISHED) != joined:
        _relax()


@njit(cache=True, nogil=True)
def _join(share: np.ndarray) -> bool:
    """A helper's claim on a call: False once the caller has closed it."""
    return atomic_add(share, JOINED, 1) < CLOSED


@njit(cache=True, nogil=True)
def _finish_and_wait(control: np.ndarray, share: np.ndarray, joined: bool, calls: int,
                     spins: int) -> int:
    """Report the last call finished (if joined), then spin until a new call is posted or
    ``spins`` turns have passed; returns the calls posted (``calls`` if none)."""
    if joined:
        atomic_add(share, FINISHED, 1)
    for turn in range(spins):
        now = atomic_load(control, CALLS)
        if now != calls:
            return now
        _relax()
        if turn % _PAUSES_PER_YIELD == _PAUSES_PER_YIELD - 1:
            _yield_core()
    return calls


def _spins_for(seconds: float) -> int:
    """Spin turns that last about ``seconds`` on this machine (timed once)."""
    control, share = np.zeros(SHARE_SLOTS, np.int64), np.zeros(SHARE_SLOTS, np.int64)
    turns = 20_000
    _finish_and_wait(control, share, False, 0, 1)  # compiled before timing
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        _finish_and_wait(control, share, False, 0, turns)
        best = min(best, time.perf_counter() - start)
    return max(1, int(turns * seconds / max(best, 1e-9)))


class Helpers:
    """``count`` daemon threads that join the caller in ``run``'s kernel calls."""

    def __init__(self, count: int) -> None:
        self.control = np.zeros(SHARE_SLOTS, np.int64)
        self._spins = _spins_for(SPIN_SECONDS)
        self._job: tuple[Callable[..., None], tuple[Any, ...], np.ndarray] | None = None
        self._wake = threading.Condition()
        self._sleeping = 0
        self._stopped = False
        self._error: BaseException | None = None
        self._threads = [threading.Thread(target=self._serve, name=f"mimics-helper-{i}",
                                          daemon=True) for i in range(count)]
        for thread in self._threads:
            thread.start()

    def run(self, kernel: Callable[..., None], args: tuple[Any, ...]) -> None:
        """``kernel(*args, control, share, True)`` here, with the helpers that come."""
        share = np.zeros(SHARE_SLOTS, np.int64)
        self._job = (kernel, args, share)
        if self._sleeping:  # read without the lock: a helper missed now helps next time
            with self._wake:
                self._wake.notify_all()
        kernel(*args, self.control, share, True)
        if share[FAILED]:  # never silent: the failed helper's chunks hold garbage
            raise RuntimeError("a helper thread's kernel call failed") from self._error

    def stop(self) -> None:
        """End the threads (they may be in the middle of a spin: it ends within
        ``SPIN_SECONDS``)."""
        self._stopped = True
        self._job = None
        self.control[CALLS] += 1
        with self._wake:
            self._wake.notify_all()

    def _serve(self) -> None:
        calls, share, joined = int(self.control[CALLS]), np.zeros(SHARE_SLOTS, np.int64), False
        while not self._stopped:
            now = _finish_and_wait(self.control, share, joined, calls, self._spins)
            joined = False
            if now == calls:
                now = self._sleep(calls)
            calls = now
            job = self._job
            if job is None:
                continue
            kernel, args, share = job
            if _join(share):
                joined = True  # reported by the next wait, even if the kernel raised
                try:
                    kernel(*args, self.control, share, False)
                except BaseException as error:  # handed to the caller, which raises it
                    self._error = error
                    share[FAILED] = 1

    def _sleep(self, calls: int) -> int:
        with self._wake:
            self._sleeping += 1
            try:
                while self.control[CALLS] == calls and not self._stopped:
                    self._wake.wait()
            finally:
                self._sleeping -= 1
        return int(self.control[CALLS])


_helpers: dict[int, Helpers] = {}


def helpers(count: int) -> Helpers:
    """This process's ``count`` helper threads (started on first use)."""
    found = _helpers.get(count)
    if found is None:
        found = _helpers[count] = Helpers(count)
    return found


def _stop_all() -> None:
    for found in _helpers.values():
        found.stop()


atexit.register(_stop_all)
# a forked child has none of its parent's threads: it starts its own
os.register_at_fork(after_in_child=_helpers.clear)


def solo_arrays() -> tuple[np.ndarray, np.ndarray]:
    """``control`` and ``share`` for a call on the calling thread alone."""
    return np.zeros(SHARE_SLOTS, np.int64), np.zeros(SHARE_SLOTS, np.int64)
