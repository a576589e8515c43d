"""The paired success-rate difference against Newcombe's published figures, hand
computations from his formulas, SciPy's binomial test and hypothesis properties."""

from __future__ import annotations

import doctest
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats as scipy_stats

from mimics.batteries import paired_rates
from mimics.batteries.paired_rates import (
    mcnemar_exact_p,
    newcombe_interval,
    paired_proportion_difference,
)

Z = 1.959963984540054  # the normal's 97.5% quantile


def outcomes(both: int, only_candidate: int, only_baseline: int,
             neither: int) -> tuple[list[int], list[int]]:
    """Paired 0/1 runs laid out from the four cells of a paired 2x2 table."""
    candidate = [1] * both + [1] * only_candidate + [0] * only_baseline + [0] * neither
    baseline = [1] * both + [0] * only_candidate + [1] * only_baseline + [0] * neither
    return candidate, baseline


# Newcombe (1998) Table II, method 10, as printed to four decimals (also the figures the
# R package propint tests against): cells (e, f, g, h) = (both, only first, only second,
# neither), then the difference and the interval's ends
NEWCOMBE_TABLE_II = [
    ((36, 12, 2, 0), 0.2, 0.0569, 0.3404),
    ((18, 12, 2, 18), 0.2, 0.0562, 0.3290),
    ((53, 0, 0, 1), 0.0, -0.0729, 0.0729),
    ((0, 30, 0, 0), 1.0, 0.8395, 1.0),
]


@pytest.mark.parametrize(("cells", "difference", "low", "high"), NEWCOMBE_TABLE_II)
def test_newcombes_published_examples(cells: tuple[int, int, int, int], difference: float,
                                      low: float, high: float) -> None:
    found = paired_proportion_difference(*outcomes(*cells))
    assert found.interval.estimate == pytest.approx(difference, abs=1e-12)
    assert found.interval.low == pytest.approx(low, abs=5e-5)
    assert found.interval.high == pytest.approx(high, abs=5e-5)
    assert found.interval.n == sum(cells)


def hand_wilson(successes: int, n: int) -> tuple[float, float]:
    """Wilson's score interval from its closed form (Newcombe 1998, eq. for method 3)."""
    p = successes / n
    root = Z * math.sqrt(Z * Z + 4 * n * p * (1 - p))
    return ((2 * n * p + Z * Z - root) / (2 * (n + Z * Z)),
            (2 * n * p + Z * Z + root) / (2 * (n + Z * Z)))


def hand_method_10(e: int, f: int, g: int, h: int) -> tuple[float, float]:
    """Newcombe's method 10 written out from the paper, independently of the module."""
    n = e + f + g + h
    p1, p2 = (e + f) / n, (e + g) / n
    l1, u1 = hand_wilson(e + f, n)
    l2, u2 = hand_wilson(e + g, n)
    product = (e + f) * (g + h) * (e + g) * (f + h)
    cross = e * h - f * g
    numerator = max(cross - n / 2, 0) if cross > 0 else cross
    phi = numerator / math.sqrt(product) if product else 0.0
    delta = math.sqrt((p1 - l1) ** 2 - 2 * phi * (p1 - l1) * (u2 - p2) + (u2 - p2) ** 2)
    epsilon = math.sqrt((u1 - p1) ** 2 - 2 * phi * (u1 - p1) * (p2 - l2) + (p2 - l2) ** 2)
    return p1 - p2 - delta, p1 - p2 + epsilon


@pytest.mark.parametrize("cells", [
    (5, 10, 8, 2),    # negative association: phi uncorrected and negative
    (20, 3, 4, 1),    # weak positive association: the correction sets phi to 0
    (30, 6, 1, 13),   # strong positive association: phi = (eh - fg - n/2) / sqrt(...)
    (0, 7, 3, 0),     # two margins zero: phi = 0
    (2, 0, 9, 4),
])
def test_method_10_against_a_hand_computation(cells: tuple[int, int, int, int]) -> None:
    low, high = hand_method_10(*cells)
    found = newcombe_interval(*cells)
    assert (found.low, found.high) == pytest.approx((max(-1.0, low), min(1.0, high)), abs=1e-9)


def test_all_pairs_candidate_only_is_not_a_point() -> None:
    # the reviewer's case: every pair (1, 0); a t interval on the differences is [1, 1]
    found = paired_proportion_difference([1] * 20, [0] * 20)
    assert found.interval.estimate == 1.0 and found.interval.high == 1.0
    # phi is 0 (zero margins): the lower end is 1 - sqrt(2) (1 - Wilson low of 20/20)
    wilson_low = hand_wilson(20, 20)[0]
    assert wilson_low == pytest.approx(0.8389, abs=5e-5)  # published Wilson tables
    assert found.interval.low == pytest.approx(1 - math.sqrt(2) * (1 - wilson_low), abs=1e-9)
    assert found.interval.low < 0.8
    assert not found.interval.degenerate
    assert found.p_value == pytest.approx(2 * 0.5 ** 20, rel=1e-12)


def test_mcnemar_exact_p_against_scipy_and_a_hand_computation() -> None:
    # 4 pairs only the candidate won, 1 only the baseline: P(X <= 1 | 5, 1/2) = 6/32, doubled
    assert mcnemar_exact_p(4, 1) == pytest.approx(12 / 32, rel=1e-12)
    assert mcnemar_exact_p(3, 0) == pytest.approx(2 / 8, rel=1e-12)
    for b, c in [(12, 2), (0, 9), (7, 7), (30, 18)]:
        found = paired_proportion_difference(*outcomes(5, b, c, 4))
        assert found.p_value == pytest.approx(scipy_stats.binomtest(b, b + c, 0.5).pvalue,
                                              rel=1e-12)
        assert found.note == ""


def test_no_discordant_pairs_and_no_pairs_say_so() -> None:
    tied = paired_proportion_difference([1, 0, 1], [1, 0, 1])
    assert tied.p_value is None and "no discordant pairs" in tied.note
    assert tied.interval.low < 0.0 < tied.interval.high
    empty = paired_proportion_difference([], [])
    assert empty.p_value is None and empty.note == "no pairs" and empty.interval.n == 0
    assert math.isnan(empty.interval.estimate)
    undefined = paired_proportion_difference([math.nan, 1.0], [0.0, math.nan])
    assert undefined.note == "no pairs"


def test_pairs_with_nan_are_left_out() -> None:
    found = paired_proportion_difference([1, 1, math.nan, 0, 1], [0, math.nan, 1, 0, 1])
    assert found.interval.n == 3
    assert found.interval == newcombe_interval(1, 1, 0, 1)
    # booleans are 0/1 runs too
    assert paired_proportion_difference(np.array([True, False]), np.array([False, False])) \
        .interval == newcombe_interval(0, 1, 0, 1)


def test_bad_input_is_named() -> None:
    with pytest.raises(ValueError, match="differ in length"):
        paired_proportion_difference([1, 0], [1])
    with pytest.raises(ValueError, match=r"candidate: expected 0, 1 or NaN.*got 2"):
        paired_proportion_difference([2, 0], [1, 0])
    with pytest.raises(ValueError, match=r"baseline: expected 0, 1 or NaN.*got 0.5"):
        paired_proportion_difference([1, 0], [1, 0.5])
    with pytest.raises(ValueError, match="non-negative"):
        newcombe_interval(1, -1, 0, 0)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 1), st.integers(0, 1)), min_size=1, max_size=80))
def test_interval_holds_the_estimate_within_minus_one_and_one(
        pairs: list[tuple[int, int]]) -> None:
    candidate = [a for a, _ in pairs]
    baseline = [b for _, b in pairs]
    found = paired_proportion_difference(candidate, baseline).interval
    assert found.estimate == pytest.approx((sum(candidate) - sum(baseline)) / len(pairs))
    assert -1.0 <= found.low <= found.estimate <= found.high <= 1.0
    assert found.high > found.low
    assert found.n == len(pairs)
    # swapping the arms mirrors the interval
    mirrored = paired_proportion_difference(baseline, candidate).interval
    assert (mirrored.low, mirrored.high) == pytest.approx((-found.high, -found.low), abs=1e-12)


def test_docstring_examples() -> None:
    assert doctest.testmod(paired_rates).failed == 0
