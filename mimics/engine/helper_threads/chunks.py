"""The kernel's side of helper threads: chunks shared through atomic counters.

A kernel run by ``kernel_threads`` takes ``(..., control, share, role, until)``
as its last arguments and loops::

    begin(control, share, role)
    chunk = take(share, role, until, chunks)
    while chunk >= 0:
        ...  # compute the chunk
        chunk_done(share, chunk)
        chunk = take(share, role, until, chunks)
    end(share, role, until, chunks)

These helpers are inlined into the kernels that use them, and Numba's disk
cache looks at a kernel's own file only: after an edit here, delete the
cached kernels (``find mimics -name '*.nb[ic]' -delete``), or ``ray_kernel.py``,
``motion_checks.py`` and ``ranger_noise.py`` keep running the old code. An installed release is
never stale (every file is rewritten).
"""

from __future__ import annotations

import platform
import sys
from typing import Any

import numpy as np
from llvmlite import ir
from numba import njit, types
from numba.core import cgutils
from numba.extending import intrinsic

# slots of the arrays below, one cache line (8 int64) apart so that threads writing
# different slots do not share a line
CALLS = 0  # control: calls posted so far
# share: next chunk, helpers joined, helpers finished, a helper's kernel raised, helpers
# wanted at most, whether the caller has begun, two tallies the kernel's threads add to
# (see tally), chunks taken (from either end), chunks taken from the back; then one flag
# per chunk, set once it is computed
NEXT, JOINED, FINISHED, FAILED, LIMIT, BEGUN = 0, 8, 16, 24, 32, 40
TALLIES = (48, 56)
TAKEN, FROM_BACK = 64, 72
CLOSED = 1 << 40  # added to JOINED by the caller when it has no chunk left
SHARE_SLOTS = 80
# a kernel call's role: the caller of a call it waits for (run); a helper; the caller of
# a call it goes on beside (start: the first chunks; end: all the others; back: chunks
# from the back until a given one is done)
LEAD, HELPER, START, END, BACK = 0, 1, 2, 3, 4
PAUSES_PER_YIELD = 64

X86 = platform.machine().lower() in ("x86_64", "amd64", "i386", "i686")
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
def relax(typingctx: Any) -> Any:
    """A spin loop's pause (x86 ``pause``: lets the sibling hyperthread run; else nothing)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        if X86:
            pause = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(ir.VoidType(), []), "llvm.x86.sse2.pause")
            builder.call(pause, [])
        return context.get_dummy_value()
    return types.void(), codegen


@intrinsic
def yield_core(typingctx: Any) -> Any:
    """``sched_yield()``: another runnable thread on this core goes first (POSIX only)."""
    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        if _YIELDS:
            call = cgutils.get_or_insert_function(
                builder.module, ir.FunctionType(ir.IntType(32), []), "sched_yield")
            builder.call(call, [])
        return context.get_dummy_value()
    return types.void(), codegen


@njit(cache=True, nogil=True, inline="always")
def begin(control: np.ndarray, share: np.ndarray, role: int) -> None:
    """The caller starting a call lets helpers join (none joins before: what the
    kernel wrote until then is theirs to read) and wakes the spinning ones."""
    if role in (LEAD, START):
        atomic_add(share, BEGUN, 1)
        atomic_add(control, CALLS, 1)


@njit(cache=True, nogil=True, inline="always")
def _is_done(share: np.ndarray, chunk: int) -> bool:
    return atomic_load(share, SHARE_SLOTS + chunk) != 0


@njit(cache=True, nogil=True, inline="always")
def take(share: np.ndarray, role: int, until: int, chunks: int) -> int:
    """The next chunk this thread computes, or -1: none left, or (start) chunk ``until``
    is done and a helper has joined (the caller stays in the kernel, without the GIL,
    until a helper that slept has woken and taken the GIL to join), or (back) chunk
    ``until`` is done. Chunks are taken in order, except by the back role, which takes
    the last ones left: one count of the chunks taken keeps the two ends apart."""
    if role == START and _is_done(share, until) and atomic_load(share, JOINED) > 0:
        return -1
    if role == BACK and _is_done(share, until):
        return -1
    if atomic_add(share, TAKEN, 1) >= chunks:
        return -1
    if role == BACK:
        return chunks - 1 - atomic_add(share, FROM_BACK, 1)
    return atomic_add(share, NEXT, 1)


@njit(cache=True, nogil=True, inline="always")
def chunk_done(share: np.ndarray, chunk: int) -> None:
    """Publish a computed chunk (its results are written before the flag)."""
    atomic_add(share, SHARE_SLOTS + chunk, 1)


@njit(cache=True, nogil=True, inline="always")
def tally(share: np.ndarray, which: int, value: int) -> None:
    """Add a thread's count to tally ``which`` (0 or 1) of the call: read it as
    ``share[TALLIES[which]]`` once the call is over."""
    atomic_add(share, TALLIES[which], value)


@njit(cache=True, nogil=True, inline="always")
def end(share: np.ndarray, role: int, until: int, chunks: int) -> None:
    """A kernel's last act. The caller of ``run`` closes the call and waits for the
    helpers that joined; ``start`` and ``back`` wait for chunk ``until``, ``end`` closes
    the call and waits for every chunk (a failed helper's chunk never comes: the flag
    ends the wait)."""
    if role == LEAD:
        joined = atomic_add(share, JOINED, CLOSED)
        while atomic_load(share, FINISHED) != joined:
            relax()
    elif role in (START, BACK):
        _await_chunks(share, until, until + 1)
    elif role == END:
        atomic_add(share, JOINED, CLOSED)
        _await_chunks(share, 0, chunks)


@njit(cache=True, nogil=True, inline="always")
def _await_chunks(share: np.ndarray, first: int, stop: int) -> None:
    """Wait until chunks ``first`` to ``stop - 1`` are done, or a helper has failed."""
    for chunk in range(first, stop):
        while not _is_done(share, chunk) and atomic_load(share, FAILED) == 0:
            relax()


# A kernel only ever called with ``Helpers.run`` (roles LEAD and HELPER, never started,
# looked at or helped from the back) can loop on these instead, which compile in a
# fraction of the time of the whole set above (0.6 s less for the ranger's noise):
#
#     begin_run(control, share, role)
#     chunk = next_chunk(share)
#     while chunk < chunks:
#         ...  # compute the chunk
#         chunk = next_chunk(share)
#     end_run(share, role)


@njit(cache=True, nogil=True, inline="always")
def begin_run(control: np.ndarray, share: np.ndarray, role: int) -> None:
    """:func:`begin` for a ``run`` call."""
    if role == LEAD:
        atomic_add(share, BEGUN, 1)
        atomic_add(control, CALLS, 1)


@njit(cache=True, nogil=True, inline="always")
def next_chunk(share: np.ndarray) -> int:
    """The next chunk of a ``run`` call (the chunks' count or more: none left)."""
    return atomic_add(share, NEXT, 1)


@njit(cache=True, nogil=True, inline="always")
def end_run(share: np.ndarray, role: int) -> None:
    """:func:`end` for a ``run`` call: its caller closes it and waits for the helpers
    that joined."""
    if role == LEAD:
        joined = atomic_add(share, JOINED, CLOSED)
        while atomic_load(share, FINISHED) != joined:
            relax()
