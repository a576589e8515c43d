"""Hall's skewness-corrected interval of a mean against independent truth: the cubic
solved by root finding (not the closed form), the skewness by hand and by SciPy, the
plain t interval on symmetric samples, and coverage on lognormal and normal draws."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import optimize
from scipy import stats as scipy_stats

from mimics.batteries.stats import sample_skewness, skew_corrected_interval, t_interval


def hall_by_root_finding(values: list[float] | np.ndarray) -> tuple[float, float]:
    """The interval from its definition, written out: the skewness by its sums, Student's
    quantile from SciPy, and g(T) = +-q solved numerically for T."""
    x = [float(v) for v in values]
    n = len(x)
    mean = sum(x) / n
    m2 = sum((v - mean) ** 2 for v in x) / n
    m3 = sum((v - mean) ** 3 for v in x) / n
    skew = m3 / m2 ** 1.5 * math.sqrt(n * (n - 1)) / (n - 2)  # G1, Joanes and Gill 1998
    s = math.sqrt(m2 * n / (n - 1))
    a, b = skew / (3 * math.sqrt(n)), skew / (6 * math.sqrt(n))
    q = float(scipy_stats.t.ppf(0.975, n - 1))

    def solve(u: float) -> float:
        return optimize.brentq(lambda t: t + a * t * t + a * a * t ** 3 / 3 + b - u, -1e3, 1e3,
                               xtol=1e-14, rtol=1e-14)

    return mean - s / math.sqrt(n) * solve(q), mean - s / math.sqrt(n) * solve(-q)


def test_a_right_skewed_sample_against_its_definition() -> None:
    values = [2.0, 3.0, 3.0, 4.0, 5.0, 6.0, 14.0]
    # by hand: mean 37/7; the skewness G1 equals SciPy's bias-corrected one
    assert sample_skewness(np.array(values)) == pytest.approx(
        scipy_stats.skew(values, bias=False), rel=1e-12)
    low, high = hall_by_root_finding(values)
    found = skew_corrected_interval(values)
    assert (found.estimate, found.n) == (pytest.approx(37 / 7, rel=1e-15), 7)
    assert (found.low, found.high) == pytest.approx((low, high), rel=1e-10)
    # the long right tail pushes the interval up, past the t interval's upper end
    plain = t_interval(values)
    assert found.high > plain.high and found.low > plain.low
    assert found.high - found.estimate > found.estimate - found.low


def test_a_left_skewed_sample_is_the_mirror_image() -> None:
    values = np.array([-2.0, -3.0, -3.0, -4.0, -5.0, -6.0, -14.0])
    low, high = hall_by_root_finding(values)
    found = skew_corrected_interval(values)
    assert (found.low, found.high) == pytest.approx((low, high), rel=1e-10)
    mirrored = skew_corrected_interval(-values)
    assert (found.low, found.high) == pytest.approx((-mirrored.high, -mirrored.low), rel=1e-12)


def test_conventions_follow_the_t_interval() -> None:
    assert skew_corrected_interval([]).n == 0 and math.isnan(skew_corrected_interval([]).low)
    one = skew_corrected_interval([4.0])
    assert one.estimate == 4.0 and one.half_width == math.inf
    flat = skew_corrected_interval([3.0, 3.0, 3.0])
    assert flat.degenerate
    assert skew_corrected_interval([1.0, math.nan, 3.0]) == t_interval([1.0, 3.0])
    # two values are always symmetric about their mean: the t interval to the bit
    assert skew_corrected_interval([1.0, 5.0]) == t_interval([1.0, 5.0])
    assert skew_corrected_interval([1.0, 2.0, 3.0, 4.0]) == t_interval([1.0, 2.0, 3.0, 4.0])


@settings(max_examples=200, deadline=None)
@given(st.lists(st.floats(-1e4, 1e4, allow_nan=False), min_size=2, max_size=80))
def test_the_interval_is_finite_and_holds_the_mean(values: list[float]) -> None:
    found = skew_corrected_interval(values)
    assert math.isfinite(found.low) and math.isfinite(found.high)
    assert found.low <= found.estimate <= found.high
    assert found.n == len(values)


@settings(max_examples=150, deadline=None)
@given(st.lists(st.floats(0.01, 100.0, allow_nan=False), min_size=1, max_size=30),
       st.floats(-50.0, 50.0, allow_nan=False))
def test_a_symmetric_sample_gets_the_t_interval(offsets: list[float], centre: float) -> None:
    values = [centre + d for d in offsets] + [centre - d for d in offsets]
    found, plain = skew_corrected_interval(values), t_interval(values)
    assert found.estimate == plain.estimate
    scale = max(plain.half_width, 1.0)  # the sample skewness is 0 up to rounding
    assert found.low == pytest.approx(plain.low, abs=1e-9 * scale)
    assert found.high == pytest.approx(plain.high, abs=1e-9 * scale)


def coverage(draw: object, n: int, truth: float, samples: int, seed: int
             ) -> tuple[float, float]:
    rng = np.random.default_rng(seed)
    hall = plain = 0
    for _ in range(samples):
        values = draw(rng, n)  # type: ignore[operator]
        found, t = skew_corrected_interval(values), t_interval(values)
        hall += found.low <= truth <= found.high
        plain += t.low <= truth <= t.high
    return hall / samples, plain / samples


def test_it_covers_a_lognormal_mean_where_the_t_interval_does_not() -> None:
    # lognormal sigma 1 (skewness 6.2), 40 values: here t covers 89.2%, this 93.2%
    hall, plain = coverage(lambda rng, n: rng.lognormal(0.0, 1.0, n), 40, math.exp(0.5),
                           4000, seed=48)
    assert hall >= 0.915  # 4,000 samples: standard error 0.4 points
    assert hall - plain >= 0.02


def test_it_keeps_the_t_intervals_coverage_on_normal_draws() -> None:
    hall, plain = coverage(lambda rng, n: rng.normal(4.2, 3.0, n), 10, 4.2, 4000, seed=10)
    assert 0.935 <= hall <= 0.965
    assert abs(hall - plain) <= 0.01
