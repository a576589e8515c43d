"""Helper threads share a kernel's chunks: each chunk once, helpers that come late or
fail never leave a chunk undone or a caller waiting (``kernel_threads``)."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
from numba import njit

from mimics.engine.helper_threads import threads as kernel_threads
from mimics.engine.helper_threads.chunks import begin, chunk_done, end, take
from mimics.engine.helper_threads.threads import LEAD, Helpers, solo_arrays

CALLER, HELPER = 1, 1000  # what each adds to a chunk's count


@njit(nogil=True)
def _count_chunks(counts: np.ndarray, work: int, sink: np.ndarray, control: np.ndarray,
                  share: np.ndarray, role: int, until: int) -> None:
    """Add CALLER or HELPER to each chunk taken, after ``work`` square roots."""
    chunks = counts.shape[0]
    begin(control, share, role)
    chunk = take(share, role, until, chunks)
    while chunk >= 0:
        total = 0.0
        for i in range(work):
            total += math.sqrt(i + chunk)
        sink[chunk] = total
        counts[chunk] += HELPER if role == kernel_threads.HELPER else CALLER
        chunk_done(share, chunk)
        chunk = take(share, role, until, chunks)
    end(share, role, until, chunks)


def _calls_until_helped(helpers: Helpers, calls: int, chunks: int = 40,
                        work: int = 20_000) -> tuple[int, int]:
    """Run up to ``calls`` calls; returns (calls made, chunks the helpers computed)."""
    helped = 0
    for made in range(1, calls + 1):
        counts, sink = np.zeros(chunks, np.int64), np.zeros(chunks)
        helpers.run(_count_chunks, (counts, work, sink), chunks, 1)
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
        assert helpers._job is None  # a call over is forgotten: its arrays are not kept
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


def test_a_started_call_gives_its_first_chunk_then_every_chunk_at_the_end():
    """``start`` returns once the chunk asked for is done; the helper goes on while the
    caller does other things; a chunk seen ``done`` is done; ``finish`` sees every chunk
    done once."""
    helpers = Helpers(1)
    helped, seen_done = 0, 0
    try:
        # 50 calls, and more while the helper has not had a core yet (a loaded machine)
        for call in range(2000):
            if call >= 50 and helped > 0 and seen_done > 50:
                break
            counts, sink = np.zeros(40, np.int64), np.zeros(40)
            flight = helpers.start(_count_chunks, (counts, 20_000, sink), 40, 1, 3)
            assert counts[3] in (CALLER, HELPER)
            time.sleep(0.001)  # the helper goes on meanwhile
            for chunk in range(40):
                if flight.done(chunk):
                    seen_done += 1
                    assert counts[chunk] in (CALLER, HELPER)
            flight.finish()
            assert np.all((counts == CALLER) | (counts == HELPER)), counts
            helped += int(np.count_nonzero(counts == HELPER))
        assert helped > 0
        assert seen_done > 50  # chunks beyond the first were done before the finish
    finally:
        helpers.stop()


def test_helping_a_started_call_takes_the_last_chunks_until_the_one_asked_for_is_done():
    """``help_until`` returns once its chunk is done, having computed chunks from the
    back only (the helper goes on from the front), never one twice; it does not finish
    the call: chunks between are left to the helper, and ``finish`` sees each done once."""
    helpers = Helpers(1)
    left_to_helper, from_back = 0, 0
    try:
        for _ in range(30):
            counts, sink = np.zeros(40, np.int64), np.zeros(40)
            flight = helpers.start(_count_chunks, (counts, 200_000, sink), 40, 1, 0)
            started = counts.copy()  # the caller's first chunks, from the front
            undone = np.flatnonzero(started == 0)
            if undone.size >= 3:  # (a busy machine: the caller may have done them all)
                wanted = int(undone[undone.size // 2])  # well ahead of the helper
                flight.help_until(wanted)
                assert counts[wanted] in (CALLER, HELPER)
                taken_back = np.flatnonzero((counts == CALLER) & (started == 0))
                # the caller's chunks while helping are the last ones, none skipped
                assert taken_back.size == 0 or taken_back.min() == 40 - taken_back.size, counts
                assert np.all(counts <= HELPER), counts  # nothing computed twice so far
                from_back += taken_back.size
                left_to_helper += int(np.count_nonzero(counts == 0))
            flight.finish()
            assert np.all((counts == CALLER) | (counts == HELPER)), counts
        assert left_to_helper > 0  # help_until is not a finish
        assert from_back > 0
    finally:
        helpers.stop()


def test_the_calling_thread_alone_computes_every_chunk():
    counts, sink = np.zeros(25, np.int64), np.zeros(25)
    _count_chunks(counts, 10, sink, *solo_arrays(25), LEAD, 0)
    assert np.all(counts == CALLER)


def test_a_failing_helper_makes_the_call_raise_not_return_holes():
    """A kernel raising in a helper: the caller raises once its own chunks are done."""
    def kernel(counts: np.ndarray, control: np.ndarray, share: np.ndarray, role: int,
               until: int) -> None:
        # a Python kernel, so that it can raise; the helper's first chunk fails
        chunks = counts.shape[0]
        begin(control, share, role)
        chunk = take(share, role, until, chunks)
        while chunk >= 0:
            if role == kernel_threads.HELPER:
                raise ValueError("helper failed")
            counts[chunk] += 1
            chunk_done(share, chunk)
            time.sleep(0.0005)  # lets the helper take the GIL, as a blocking call would
            chunk = take(share, role, until, chunks)
        end(share, role, until, chunks)

    helpers = Helpers(1)
    try:
        with pytest.raises(RuntimeError, match="helper") as failure:
            for _ in range(200):
                helpers.run(kernel, (np.zeros(50, np.int64),), 50, 1)
        assert isinstance(failure.value.__cause__, ValueError)
    finally:
        helpers.stop()


def test_stopped_helpers_end_their_threads():
    helpers = Helpers(2)
    helpers.run(_count_chunks, (np.zeros(4, np.int64), 10, np.zeros(4)), 4, 2)
    helpers.stop()
    for thread in helpers._threads:
        thread.join(timeout=10)
        assert not thread.is_alive()


def test_no_helper_joins_before_the_caller_begins_nor_more_than_asked_for():
    """Before the caller has begun, a claim is refused and not counted (the caller may
    still be writing what helpers read); past the call's limit it is refused and
    counted finished at once (the caller waits for every claim it did not refuse);
    after the close, refused and not counted."""
    share = np.zeros(kernel_threads.SHARE_SLOTS, np.int64)
    share[kernel_threads.LIMIT] = 1
    assert not kernel_threads._join(share)
    assert share[kernel_threads.JOINED] == 0
    begin(np.zeros(kernel_threads.SHARE_SLOTS, np.int64), share, LEAD)
    assert kernel_threads._join(share)
    assert not kernel_threads._join(share)
    assert share[kernel_threads.FINISHED] == 1
    share[kernel_threads.JOINED] += kernel_threads.CLOSED
    assert not kernel_threads._join(share)
    assert share[kernel_threads.FINISHED] == 1
    helpers = Helpers(3)  # three threads, calls of one helper: still each chunk once
    try:
        _made, helped = _calls_until_helped(helpers, 2_000)
        assert helped > 0
    finally:
        helpers.stop()


def test_every_helper_sleeps_once_idle():
    """After a call, the helpers past the first sleep at once and the first once its
    spin is over: an idle run burns no core."""
    helpers = Helpers(3)
    try:
        helpers.run(_count_chunks, (np.zeros(4, np.int64), 10, np.zeros(4)), 4, 3)
        deadline = time.monotonic() + 10.0
        while helpers._sleeping < 3 and time.monotonic() < deadline:
            time.sleep(0.001)
        assert helpers._sleeping == 3
    finally:
        helpers.stop()
