"""The difference of two paired success rates: Newcombe's interval and McNemar's exact test.

Two algorithms run on the same scenarios, parameters and seeds give paired 0/1
outcomes (reached the goal or not). A t interval on their 0/1 differences is
wrong for them: when every pair is (1, 0) the differences have no spread and the
interval shrinks to the point ``1.00 [1.00, 1.00]``, although each rate's own
Wilson interval is wide. :func:`paired_proportion_difference` instead gives:

- the interval of Newcombe (1998), "Improved confidence intervals for the
  difference between binomial proportions based on paired data", Statistics in
  Medicine 17:2635-2650, method 10 (hybrid score): the two rates' Wilson score
  intervals combined with a continuity-corrected phi correlation between the
  paired outcomes;
- the p-value of McNemar's exact test: a two-sided binomial test, at 1/2, of the
  pairs where only the candidate succeeded among all discordant pairs.

>>> found = paired_proportion_difference([1] * 20, [0] * 20)
>>> found.interval.estimate, round(found.interval.low, 4), found.interval.high
(1.0, 0.7721, 1.0)
"""

from __future__ import annotations

import math

import numpy as np

from mimics.batteries.stats import Interval, PairedDifference, wilson_interval


def _paired_outcomes(candidate: np.ndarray | list[float],
                     baseline: np.ndarray | list[float]) -> tuple[np.ndarray, np.ndarray]:
    """The complete pairs as booleans (NaN pairs left out), after checking the values."""
    a = np.asarray(candidate, dtype=float)
    b = np.asarray(baseline, dtype=float)
    if a.shape != b.shape:
        raise ValueError(f"paired outcomes: candidate {a.shape} and baseline {b.shape} "
                         "differ in length")
    a, b = a.ravel(), b.ravel()
    for name, values in (("candidate", a), ("baseline", b)):
        bad = ~(np.isnan(values) | (values == 0) | (values == 1))
        if bad.any():
            raise ValueError(f"{name}: expected 0, 1 or NaN per run, got {float(values[bad][0])}")
    keep = ~(np.isnan(a) | np.isnan(b))
    return a[keep] == 1, b[keep] == 1


def _phi(both: int, only_candidate: int, only_baseline: int, neither: int) -> float:
    """Newcombe's continuity-corrected phi between the paired outcomes (0: a margin is 0)."""
    n = both + only_candidate + only_baseline + neither
    margins = ((both + only_candidate) * (only_baseline + neither)
               * (both + only_baseline) * (only_candidate + neither))
    if margins == 0:
        return 0.0
    cross = both * neither - only_candidate * only_baseline
    if cross > n / 2:
        corrected = cross - n / 2
    elif cross >= 0:
        corrected = 0.0
    else:  # Newcombe corrects only positive associations, which narrow the interval
        corrected = float(cross)
    return corrected / math.sqrt(margins)


def _combined(distance_a: float, distance_b: float, phi: float) -> float:
    """sqrt(a^2 - 2 phi a b + b^2), never the root of a rounding error below zero."""
    return math.sqrt(max(0.0, distance_a ** 2 - 2 * phi * distance_a * distance_b
                         + distance_b ** 2))


def newcombe_interval(both: int, only_candidate: int, only_baseline: int,
                      neither: int) -> Interval:
    """Newcombe's method-10 95% interval for p_candidate - p_baseline from a paired table.

    Raises:
        ValueError: when a count is negative.
    """
    counts = (both, only_candidate, only_baseline, neither)
    if min(counts) < 0:
        raise ValueError(f"paired counts: expected non-negative counts, got {counts}")
    n = sum(counts)
    if n == 0:
        return Interval(math.nan, math.nan, math.nan, 0)
    candidate = wilson_interval(both + only_candidate, n)
    baseline = wilson_interval(both + only_baseline, n)
    estimate = (only_candidate - only_baseline) / n
    phi = _phi(both, only_candidate, only_baseline, neither)
    below = _combined(candidate.estimate - candidate.low, baseline.high - baseline.estimate, phi)
    above = _combined(baseline.estimate - baseline.low, candidate.high - candidate.estimate, phi)
    return Interval(estimate, max(-1.0, estimate - below), min(1.0, estimate + above), n)


def mcnemar_exact_p(only_candidate: int, only_baseline: int) -> float:
    """McNemar's exact two-sided p-value from the discordant pairs (1 without any)."""
    discordant = only_candidate + only_baseline
    if discordant == 0:
        return 1.0
    from scipy.stats import binomtest

    return float(binomtest(only_candidate, discordant, 0.5).pvalue)


def paired_proportion_difference(candidate: np.ndarray | list[float],
                                 baseline: np.ndarray | list[float]) -> PairedDifference:
    """``p_candidate - p_baseline`` of paired 0/1 outcomes: Newcombe interval, McNemar p.

    Pairs where either value is NaN are left out; ``interval.n`` is the number of
    pairs kept.

    Raises:
        ValueError: when the two differ in length or hold values other than 0, 1, NaN.
    """
    a, b = _paired_outcomes(candidate, baseline)
    both = int(np.count_nonzero(a & b))
    only_candidate = int(np.count_nonzero(a & ~b))
    only_baseline = int(np.count_nonzero(~a & b))
    neither = int(np.count_nonzero(~a & ~b))
    interval = newcombe_interval(both, only_candidate, only_baseline, neither)
    if interval.n == 0:
        return PairedDifference(interval, None, "no pairs")
    if only_candidate + only_baseline == 0:  # not counted among the tests made
        return PairedDifference(interval, None, f"no discordant pairs among {interval.n}: "
                                "nothing for McNemar's test to weigh")
    return PairedDifference(interval, mcnemar_exact_p(only_candidate, only_baseline), "")
