"""The step's shortcuts give what the long way gives (timing batches, stall check)."""

from __future__ import annotations

import numpy as np

from mimics.engine.outcome import TimingStats
from mimics.engine.stall import StallDetector
from mimics.engine.state import WorldState
from mimics.scenarios.line import scenario as line


def test_timing_batches_give_the_histogram_of_one_at_a_time() -> None:
    rng = np.random.default_rng(3)
    values = rng.lognormal(-11, 2, 3 * TimingStats._HELD + 77)
    single, batch = TimingStats(), TimingStats()
    for value in values[:700]:
        single.add(np.array([value]))
    batch.add(values[:700])
    for q in (5, 50, 95, 99.9):
        assert single.percentile(q) == batch.percentile(q)
    assert np.array_equal(single._histogram, batch._histogram)
    stream = TimingStats()
    for chunk in np.array_split(values, 97):  # fills the held buffer several times
        stream.add(chunk)
    big = rng.lognormal(-11, 2, TimingStats._HELD + 5)  # more than it holds at once
    stream.add(big)
    everything = np.concatenate([values, big])
    assert stream.count == len(everything) and stream.maximum == float(everything.max())
    stream.percentile(50)  # bins what is held
    binned = np.bincount(np.searchsorted(TimingStats._EDGES, everything),
                         minlength=len(TimingStats._EDGES) + 1)
    assert np.array_equal(stream._histogram, binned)


def test_quiet_stall_flags_equal_the_full_check() -> None:
    scenario = line(robots=4)
    state = WorldState.from_scenario(scenario, 1)
    quick = StallDetector(scenario.settings, state.n)
    flags = quick.update(state)
    assert flags.changes == 0
    for flag in flags[:4]:
        assert flag.dtype == bool and flag.shape == (4,) and not flag.any()
    # a robot marked stalled always takes the full path: its end is reported
    state.in_livelock[2] = True
    flags = quick.update(state)
    assert flags.livelock_ended.tolist() == [False, False, True, False]
    assert not state.in_livelock.any()

