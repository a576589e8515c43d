"""The battery statistics against independent truth: coverage on synthetic data of known
distribution, hand computations, and SciPy as the reference for the signed-rank test."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats as scipy_stats

from mimics.batteries.stats import (
    paired_difference,
    proportion_interval,
    t_interval,
    wilson_interval,
)


@pytest.mark.parametrize(("n", "sigma"), [(5, 1.0), (10, 3.0), (30, 0.2)])
def test_t_intervals_cover_the_true_mean_95_percent_of_the_time(n: int, sigma: float) -> None:
    rng = np.random.default_rng(20261126 + n)
    true_mean = 4.2
    draws = 2000
    covered = sum(
        (found := t_interval(rng.normal(true_mean, sigma, n))).low <= true_mean <= found.high
        for _ in range(draws))
    assert covered / draws >= 0.93
    assert covered / draws <= 0.97  # not an interval too wide to mean anything


def exact_coverage(n: int, p: float) -> float:
    """The probability that the Wilson interval of Binomial(n, p) successes holds p."""
    return float(sum(scipy_stats.binom.pmf(k, n, p) for k in range(n + 1)
                     if wilson_interval(k, n).low <= p <= wilson_interval(k, n).high))


@pytest.mark.parametrize(("n", "p"), [(10, 0.5), (30, 0.9), (100, 0.2), (50, 0.7)])
def test_wilson_intervals_cover_the_true_proportion(n: int, p: float) -> None:
    assert exact_coverage(n, p) >= 0.93


@pytest.mark.parametrize("n", [10, 30, 100])
def test_wilson_coverage_averaged_over_proportions(n: int) -> None:
    # Wilson's coverage oscillates with p and dips near 0 and 1 (Brown, Cai and DasGupta
    # 2001); its mean over p stays near 95%, where the normal (Wald) interval's does not
    grid = np.linspace(0.02, 0.98, 49)
    assert np.mean([exact_coverage(n, p) for p in grid]) >= 0.93


def test_wilson_interval_against_a_hand_computation() -> None:
    # 9 of 10: centre (0.9 + z^2/20) / (1 + z^2/10), half z/(1+z^2/10) sqrt(0.09/10 + z^2/400)
    z = 1.959963984540054
    centre = (0.9 + z * z / 20) / (1 + z * z / 10)
    half = z / (1 + z * z / 10) * math.sqrt(0.9 * 0.1 / 10 + z * z / 400)
    found = wilson_interval(9, 10)
    assert found.estimate == 0.9
    assert found.low == pytest.approx(centre - half, rel=1e-12)
    assert found.high == pytest.approx(centre + half, rel=1e-12)
    assert (round(found.low, 4), round(found.high, 4)) == (0.5958, 0.9821)  # published tables
    assert wilson_interval(10, 10).high == 1.0 and wilson_interval(0, 10).low == 0.0
    assert proportion_interval([1.0, 0.0, math.nan, 1.0]).n == 3
    with pytest.raises(ValueError, match="successes"):
        wilson_interval(11, 10)


def test_t_interval_against_a_hand_computation() -> None:
    values = [2.0, 4.0, 9.0]  # mean 5, s = sqrt(13)
    # Student's t with 2 degrees of freedom in closed form: (2q - 1) / sqrt(2q(1 - q))
    t_2 = 0.95 / math.sqrt(2 * 0.975 * 0.025)
    found = t_interval(values)
    half = t_2 * math.sqrt(13.0) / math.sqrt(3.0)
    assert (found.estimate, found.n) == (5.0, 3)
    assert found.low == pytest.approx(5.0 - half, rel=1e-12)
    assert found.half_width == pytest.approx(half, rel=1e-12)
    assert t_interval([7.0]).half_width == math.inf and t_interval([]).n == 0
    assert t_interval([1.0, math.nan, 3.0]).estimate == 2.0  # undefined values left out


def test_paired_difference_against_a_hand_computation_and_scipy() -> None:
    candidate = np.array([12.1, 9.8, 11.5, 10.2, 13.0, 9.1, 10.7, 12.5, 11.0, 10.0])
    baseline = np.array([11.0, 10.0, 10.1, 9.9, 11.2, 9.5, 10.0, 11.0, 10.4, 10.1])
    differences = candidate - baseline  # 1.1 -0.2 1.4 0.3 1.8 -0.4 0.7 1.5 0.6 -0.1
    mean = 6.7 / 10
    s = math.sqrt(sum((d - mean) ** 2 for d in differences) / 9)
    half = 2.2621571627409915 * s / math.sqrt(10)  # t(0.975, 9), from tables
    found = paired_difference(candidate, baseline)
    assert found.interval.estimate == pytest.approx(mean, rel=1e-12)
    assert (found.interval.low, found.interval.high) == pytest.approx(
        (mean - half, mean + half), rel=1e-9)
    assert found.interval.n == 10 and found.note == ""
    assert found.p_value == pytest.approx(scipy_stats.wilcoxon(differences).pvalue, rel=1e-12)
    # the exact null distribution by brute force: the negative differences (0.1, 0.2, 0.4)
    # have ranks 1, 2 and 4 (W- = 7); count the 2^10 sign patterns with W- <= 7
    ranks = np.arange(1, 11)
    low_tail = sum(1 for signs in range(1024)
                   if sum(r for r in ranks if signs >> (r - 1) & 1) <= 7)
    assert low_tail == 19
    assert found.p_value == pytest.approx(2 * low_tail / 1024, rel=1e-9)


def test_paired_difference_says_why_there_is_no_p_value() -> None:
    same = paired_difference([3.0] * 8, [3.0] * 8)
    assert same.p_value is None and same.note == "all 8 differences are zero"
    assert (same.interval.low, same.interval.high) == (0.0, 0.0)
    few = paired_difference([1.0, 2.0, 3.0, 4.0, 5.0, 6.0], [0.0, 1.0, 2.0, 3.0, 4.0, 6.0])
    assert few.p_value is None and "only 5 non-zero" in few.note
    assert paired_difference([], []).note == "no pairs"
    # pairs with an undefined value (a time to goal never reached) are left out
    left = paired_difference([1.0, math.nan, 3.0], [0.5, 2.0, math.nan])
    assert left.interval.n == 1 and left.interval.estimate == 0.5
    with pytest.raises(ValueError, match="differ in length"):
        paired_difference([1.0], [1.0, 2.0])


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-100, 100, allow_nan=False), min_size=6, max_size=40),
       st.floats(-5, 5, allow_nan=False))
def test_shifting_both_arms_changes_nothing(values: list[float], shift: float) -> None:
    rng = np.random.default_rng(len(values))
    baseline = np.array(values)
    candidate = baseline + rng.normal(0.5, 1.0, len(values))
    plain = paired_difference(candidate, baseline)
    shifted = paired_difference(candidate + shift, baseline + shift)
    assert shifted.interval.estimate == pytest.approx(plain.interval.estimate, abs=1e-6)
    assert shifted.interval.n == plain.interval.n
    if plain.p_value is not None and shifted.p_value is not None:
        reference = scipy_stats.wilcoxon(candidate - baseline).pvalue
        assert plain.p_value == pytest.approx(reference, rel=1e-9)
