"""Helper threads share a kernel's chunks: each chunk once, helpers that come late or
fail never leave a chunk undone or a caller waiting (``kernel_threads``)."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from numba import njit

from mimics.engine import kernel_threads
from mimics.engine.kernel_threads import (
    Helpers,
    close_call,
    next_chunk,
    open_call,
    solo_arrays,
)

CALLER, HELPER = 1, 1000  # what each adds to a chunk's count


@njit(nogil=True)
def _count_chunks(counts: np.ndarray, work: int, sink: np.ndarray, control: np.ndarray,
                  share: np.ndarray, lead: bool) -> None:
    """Add CALLER or HELPER to each chunk taken, after ``work`` square roots."""
    if lead:
        open_call(control)
    chunk = next_chunk(share)
    while chunk < counts.shape[0]:
        total = 0.0
        for i in range(work):
            total += math.sqrt(i + chunk)
        sink[chunk] = total
        counts[chunk] += CALLER if lead else HELPER
        chunk = next_chunk(share)
    if lead:
        close_call(share)


def _calls_until_helped(helpers: Helpers, calls: int, chunks: int = 40,
                        work: int = 20_000) -> tuple[int, int]:
    """Run up to ``calls`` calls; returns (calls made, chunks the helpers computed)."""
    helped = 0
    for made in range(1, calls + 1):
        counts, sink = np.zeros(chunks, np.int64), np.zeros(chunks)
        helpers.run(_count_chunks, (counts, work, sink))
        # every chunk exactly once, by the caller or by one helper
        assert np.all((counts == CALLER) | (counts == HELPER)), counts
        helped += int(np.count_nonzero(counts == HELPER))
        if helped and made >= 20:
            return made, helped
    return calls, helped


def test_each_chunk_is_computed_once_and_the_helper_takes_some():
    helpers = Helpers(1)
    try:
        _made, helped = _calls_until_helped(helpers, 2_000)
        assert helped > 0
    finally:
        helpers.stop()


def test_a_sleeping_helper_is_woken_by_the_next_call(monkeypatch: pytest.MonkeyPatch):
    """With no spin at all the helper sleeps after every call: each call wakes it, and it
    joins while chunks are left (or finds the call closed and does nothing)."""
    monkeypatch.setattr(kernel_threads, "SPIN_SECONDS", 0.0)
    helpers = Helpers(1)
    try:
        _made, helped = _calls_until_helped(helpers, 2_000, work=200_000)
        assert helped > 0
    finally:
        helpers.stop()


def test_the_calling_thread_alone_computes_every_chunk():
    counts, sink = np.zeros(25, np.int64), np.zeros(25)
    _count_chunks(counts, 10, sink, *solo_arrays(), True)
    assert np.all(counts == CALLER)


def test_a_failing_helper_makes_the_call_raise_not_return_holes():
    """A kernel raising in a helper: the caller raises once its own chunks are done."""
    def kernel(counts: np.ndarray, control: np.ndarray, share: np.ndarray,
               lead: bool) -> None:
        # a Python kernel, so that it can raise; the helper's first chunk fails
        if lead:
            open_call(control)
        chunk = next_chunk(share)
        while chunk < counts.shape[0]:
            if not lead:
                raise ValueError("helper failed")
            counts[chunk] += 1
            time.sleep(0.0005)  # lets the helper take the GIL, as a blocking call would
            chunk = next_chunk(share)
        if lead:
            close_call(share)

    helpers = Helpers(1)
    try:
        with pytest.raises(RuntimeError, match="helper") as failure:
            for _ in range(200):
                helpers.run(kernel, (np.zeros(50, np.int64),))
        assert isinstance(failure.value.__cause__, ValueError)
    finally:
        helpers.stop()


def test_stopped_helpers_end_their_threads():
    helpers = Helpers(2)
    helpers.run(_count_chunks, (np.zeros(4, np.int64), 10, np.zeros(4)))
    helpers.stop()
    for thread in helpers._threads:
        thread.join(timeout=10)
        assert not thread.is_alive()
