"""The BCa bootstrap interval against SciPy called directly, and the degenerate flag."""

from __future__ import annotations

import doctest
import math

import numpy as np
import pytest
from scipy import stats as scipy_stats

from mimics.batteries import stats
from mimics.batteries.stats import Interval, bootstrap_interval, t_interval, wilson_interval


def scipy_bca(values: np.ndarray, seed: int, resamples: int) -> tuple[float, float]:
    result = scipy_stats.bootstrap((values,), np.mean, n_resamples=resamples,
                                   confidence_level=0.95, method="BCa",
                                   random_state=np.random.default_rng(seed))
    return float(result.confidence_interval.low), float(result.confidence_interval.high)


@pytest.mark.parametrize("seed", [0, 7])
def test_bootstrap_matches_scipy_with_the_same_seed(seed: int) -> None:
    times = np.random.default_rng(3).lognormal(2.0, 0.8, 40)  # skewed, as times to goal are
    found = bootstrap_interval(np.append(times, math.nan), seed=seed, resamples=2000)
    assert (found.low, found.high) == scipy_bca(times, seed, 2000)
    assert found.estimate == pytest.approx(times.mean(), rel=1e-12) and found.n == 40
    assert found.low < found.estimate < found.high
    # skewed data: the upper half is the longer one, unlike the t interval's
    assert found.high - found.estimate > found.estimate - found.low
    assert bootstrap_interval(times, seed=seed, resamples=2000) == found  # reproducible


def test_bootstrap_default_resamples_match_scipy() -> None:
    values = np.array([3.1, 4.0, 2.2, 5.9, 4.4, 3.3, 8.0, 2.9])
    found = bootstrap_interval(values)
    assert (found.low, found.high) == scipy_bca(values, 0, 9999)


def test_bootstrap_follows_the_t_interval_conventions() -> None:
    for values in ([], [math.nan], [4.0], [2.5, 2.5, 2.5], [1.0, math.nan, 1.0]):
        found, expected = bootstrap_interval(values), t_interval(values)
        assert found.n == expected.n
        for mine, theirs in ((found.estimate, expected.estimate), (found.low, expected.low),
                             (found.high, expected.high)):
            assert mine == theirs or (math.isnan(mine) and math.isnan(theirs))
    with pytest.raises(ValueError, match="resamples"):
        bootstrap_interval([1.0, 2.0], resamples=0)


def test_degenerate_flags_a_sample_without_spread() -> None:
    assert t_interval([3.0, 3.0, 3.0]).degenerate
    assert bootstrap_interval([0.0] * 5).degenerate
    assert Interval(1.0, 1.0, 1.0, 20).degenerate  # positional construction still works
    assert not t_interval([1.0, 2.0]).degenerate
    assert not t_interval([3.0]).degenerate  # no interval at all: not a point interval
    assert not t_interval([]).degenerate
    assert not Interval(1.0, 1.0, 1.0, 0).degenerate
    # a rate with every run a success still has a Wilson interval of positive width
    assert not wilson_interval(20, 20).degenerate


def test_module_docstring_examples() -> None:
    assert doctest.testmod(stats, optionflags=doctest.ELLIPSIS).failed == 0
