"""Helper threads that share a compiled kernel's chunks with the calling thread.

A kernel call of a fraction of a millisecond (a Cave scan: about 0.45 ms on
one thread) cannot afford a thread pool's hand-over: waking a sleeping
thread and waiting on a future cost 70 us here, a third of what a second
core saves. So the helpers are woken and waited for without the kernel
(futex) and without the GIL:

- The first helper spins (x86 ``pause``, and ``sched_yield`` now and then so
  a busy machine's other threads get the core) in a ``nogil`` kernel until
  the call counter in ``control`` changes, for about ``SPIN_SECONDS``;
  then it sleeps on a condition, and the next call wakes it. The others (on
  machines of more than two cores) sleep at once: a core each spinning
  through the Python part of every step would be too much to burn.
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
split (the ray kernel's rows do: ``tests/engine/helper_threads/test_threads.py``).

The calling thread may also start a call and go on with its own Python
work while the helpers take the chunks (:meth:`Helpers.start`): it then
looks whether the chunk it needs is done (:meth:`Flight.done`) and, when one
is not, computes the last chunks left, from the back, until the helpers
(going on from the front) have done it (:meth:`Flight.help_until`: one
kernel call). :meth:`Flight.finish` computes all that is left with the
helpers and waits for every chunk. A per-robot algorithm reads its robot's
scan while a helper traces the next robots' scans.

The kernel's side (the loop every such kernel runs, the counters and the
roles) is in ``kernel_chunks.py``.
"""

from __future__ import annotations

import atexit
import os
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np
from numba import config, get_num_threads, njit
from numba.np.ufunc import parallel as numba_parallel  # where get_num_threads lives

from mimics.engine.helper_threads.chunks import (
    BACK,
    BEGUN,
    CALLS,
    CLOSED,
    END,
    FAILED,
    FINISHED,
    HELPER,
    JOINED,
    LEAD,
    LIMIT,
    PAUSES_PER_YIELD,
    SHARE_SLOTS,
    START,
    X86,
    atomic_add,
    atomic_load,
    relax,
    yield_core,
)

SPIN_SECONDS = 0.001  # how long an idle helper spins before it sleeps


@njit(cache=True, nogil=True)
def _join(share: np.ndarray) -> bool:
    """A helper's claim on a call: False before the caller has begun it (the helper
    waits for the next call counted), once the caller has closed it, or when enough
    helpers have joined (that claim is reported finished at once)."""
    if atomic_load(share, BEGUN) == 0:
        return False
    before = atomic_add(share, JOINED, 1)
    if before >= CLOSED:
        return False
    if before >= atomic_load(share, LIMIT):
        atomic_add(share, FINISHED, 1)
        return False
    return True


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
        relax()
        if turn % PAUSES_PER_YIELD == PAUSES_PER_YIELD - 1:
            yield_core()
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
    """Daemon threads that join the caller's kernel calls (``run``, ``start``); as many
    as the calls have asked for at most (``grow``), each call taking up to its own
    number."""

    def __init__(self, count: int) -> None:
        self.control = np.zeros(SHARE_SLOTS, np.int64)
        self._spins = _spins_for(SPIN_SECONDS)
        self._job: tuple[Callable[..., None], tuple[Any, ...], np.ndarray] | None = None
        self._wake = threading.Condition()
        self._sleeping = 0
        self._stopped = False
        self._error: BaseException | None = None
        self._threads: list[threading.Thread] = []
        self.grow(count)

    def grow(self, count: int) -> None:
        """Have at least ``count`` threads."""
        while len(self._threads) < count:
            first = not self._threads
            thread = threading.Thread(target=self._serve, args=(first,), daemon=True,
                                      name=f"mimics-helper-{len(self._threads)}")
            self._threads.append(thread)
            thread.start()

    def run(self, kernel: Callable[..., None], args: tuple[Any, ...], chunks: int,
            count: int) -> np.ndarray:
        """``kernel(*args, control, share, LEAD, 0)`` here, with up to ``count`` helpers;
        returns the call's ``share`` (its tallies)."""
        share = self._post(kernel, args, chunks, count)
        try:
            kernel(*args, self.control, share, LEAD, 0)
        finally:
            self._release(share)
        self.check(share)
        return share

    def start(self, kernel: Callable[..., None], args: tuple[Any, ...], chunks: int,
              count: int, until: int) -> Flight:
        """Start a call of ``chunks`` chunks with up to ``count`` helpers and return once
        chunk ``until`` is done; the helpers go on with the others."""
        share = self._post(kernel, args, chunks, count)
        kernel(*args, self.control, share, START, until)
        self.check(share)
        return Flight(self, kernel, args, share)

    def check(self, share: np.ndarray) -> None:
        """Raise if a helper's kernel failed in the call of ``share``."""
        if share[FAILED]:  # never silent: the failed helper's chunks hold garbage
            raise RuntimeError("a helper thread's kernel call failed") from self._error

    def _post(self, kernel: Callable[..., None], args: tuple[Any, ...], chunks: int,
              count: int) -> np.ndarray:
        share = np.zeros(SHARE_SLOTS + chunks, np.int64)
        share[LIMIT] = count
        self._job = (kernel, args, share)
        if self._sleeping:  # read without the lock: a helper missed now helps next time
            with self._wake:
                self._wake.notify_all()
        return share

    def _release(self, share: np.ndarray) -> None:
        """Forget a call that is over (its arrays are not kept alive by the helpers)."""
        job = self._job
        if job is not None and job[2] is share:
            self._job = None

    def stop(self) -> None:
        """End the threads (they may be in the middle of a spin: it ends within
        ``SPIN_SECONDS``)."""
        self._stopped = True
        self._job = None
        self.control[CALLS] += 1
        with self._wake:
            self._wake.notify_all()

    def _serve(self, spins: bool) -> None:
        calls, share, joined = int(self.control[CALLS]), np.zeros(SHARE_SLOTS, np.int64), False
        turns = self._spins if spins else 0
        while not self._stopped:
            now = _finish_and_wait(self.control, share, joined, calls, turns)
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
                    kernel(*args, self.control, share, HELPER, 0)
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


class Flight:
    """A call started by :meth:`Helpers.start`: its chunks are computed meanwhile."""

    def __init__(self, helpers: Helpers, kernel: Callable[..., None], args: tuple[Any, ...],
                 share: np.ndarray) -> None:
        self._helpers, self._kernel, self._args, self._share = helpers, kernel, args, share
        self._flags = share[SHARE_SLOTS:]

    #: Whether :meth:`done` can see a chunk done (x86); elsewhere it always says no,
    #: so a caller waiting for a chunk had better finish the call than help it.
    looks = X86

    def done(self, chunk: int) -> bool:
        """Whether ``chunk`` is done (and its results may be read): a look, no wait."""
        # x86 keeps loads in order: a flag seen set means the chunk's results are seen
        # (elsewhere, False: the caller finishes, whose atomic waits order the loads)
        return self.looks and bool(self._flags[chunk])

    def help_until(self, chunk: int) -> None:
        """Return once ``chunk`` is done, computing the last chunks left here meanwhile
        (the helpers go on from the front: neither thread waits while chunks are left)."""
        self._kernel(*self._args, self._helpers.control, self._share, BACK, chunk)
        self._helpers.check(self._share)

    def finish(self) -> None:
        """Return once every chunk is done (computing those left here); no helper
        touches the results afterwards."""
        try:
            self._kernel(*self._args, self._helpers.control, self._share, END, 0)
        finally:
            self._helpers._release(self._share)
        self._helpers.check(self._share)


_helpers: list[Helpers] = []  # this process's, once started


def helpers(count: int) -> Helpers:
    """This process's helper threads, at least ``count`` of them (started on first use)."""
    if not _helpers:
        _helpers.append(Helpers(count))
    _helpers[0].grow(count)
    return _helpers[0]


def helpers_worth(parts: int) -> int:
    """How many helpers a call of ``parts`` parts, each worth a thread, should take: at
    most Numba's thread count less the calling thread (``NUMBA_NUM_THREADS``, or
    ``numba.set_num_threads``)."""
    return min(numba_threads(), parts) - 1 if parts > 1 else 0


def numba_threads() -> int:
    """Numba's thread count (``NUMBA_NUM_THREADS``, or ``numba.set_num_threads``) without
    starting Numba's own thread pool, which mimics never uses (5 ms, and idle threads)."""
    if getattr(numba_parallel, "_is_initialized", True):  # started (set_num_threads starts it)
        return get_num_threads()
    return int(config.NUMBA_NUM_THREADS)


def _stop_all() -> None:
    for found in _helpers:
        found.stop()


atexit.register(_stop_all)
# a forked child has none of its parent's threads: it starts its own
os.register_at_fork(after_in_child=_helpers.clear)


# a call on the calling thread alone posts to no helper: one control for all of them
_SOLO_CONTROL = np.zeros(SHARE_SLOTS, np.int64)


def solo_arrays(chunks: int) -> tuple[np.ndarray, np.ndarray]:
    """``control`` and ``share`` for a call of ``chunks`` chunks on the calling thread
    alone (role ``LEAD``)."""
    return _SOLO_CONTROL, np.zeros(SHARE_SLOTS + chunks, np.int64)
