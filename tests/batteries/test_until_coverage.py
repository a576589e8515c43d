"""The stopping rule keeps its promise: simulated batteries whose reported 95% interval, at
the cell's stop, covers the true mean at least 93% of the time.

Each simulated battery is one cell decided by the project's own :func:`cell_progress`,
and the interval checked is the one the reports print
(:func:`mimics.batteries.comparison.interval_of`). 2,000 batteries per case put the
simulation's own standard error near 0.5 points at 95% coverage. A battery's values are
drawn once per case from its own seeded stream and shared by every target; the rule gets
them all at once and walks its rounds in one call, reading seed k only once a round has
scheduled it (checked: the same stops as handing each round's values over only when
scheduled, as a running battery does; and NumPy's stream gives the same values round by
round as in one call).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from functools import cache

import numpy as np
import pytest

from mimics.batteries.comparison import interval_of
from mimics.batteries.until import DEFAULT_MAX_SEEDS, CellProgress, UntilRule, cell_progress

BATTERIES = 2000
STREAM = 48  # the seed of every case's batteries (issue 48)
PROMISED = 0.93
TARGETS = (10, 30, 100, 300)  # n*: the seeds a fixed sample would need
Z = 1.959963984540054  # the normal 97.5% quantile
Draw = Callable[[np.random.Generator, int], np.ndarray]


@dataclass(frozen=True)
class Case:
    """A metric's distribution, its true mean and standard deviation."""

    metric: str
    draw: Draw
    mean: float
    sd: float


LOGNORMAL_MEAN = math.exp(0.5)
CASES = {
    "normal": Case("path_length", lambda rng, k: rng.normal(10.0, 2.0, k), 10.0, 2.0),
    "success at rate 0.1": Case("success", lambda rng, k: (rng.random(k) < 0.1) * 1.0,
                                0.1, 0.3),
    "0/1 count at rate 0.1": Case("collisions", lambda rng, k: (rng.random(k) < 0.1) * 1.0,
                                  0.1, 0.3),
    "lognormal sigma 0.5": Case("time_to_goal", lambda rng, k: rng.lognormal(0.0, 0.5, k),
                                math.exp(0.125),
                                math.sqrt((math.exp(0.25) - 1) * math.exp(0.25))),
    "lognormal sigma 1": Case("time_to_goal", lambda rng, k: rng.lognormal(0.0, 1.0, k),
                              LOGNORMAL_MEAN, math.sqrt((math.e - 1) * math.e)),
}


def restricted_lognormal(horizon: float) -> tuple[float, float]:
    """Mean and sd of min(X, horizon) for X lognormal(0, 1): a time to goal whose
    non-arrivals count at the run's horizon, as mimics' ``time_to_goal`` does."""
    from scipy.stats import norm

    cut = math.log(horizon)
    beyond = norm.sf(cut)  # P(X > horizon)
    mean = math.exp(0.5) * norm.cdf(cut - 1.0) + horizon * beyond
    square = math.exp(2.0) * norm.cdf(cut - 2.0) + horizon ** 2 * beyond
    return mean, math.sqrt(square - mean ** 2)


HORIZON = 5.0  # five times the median time: 5.4% of runs reach it
CASES["lognormal sigma 1, horizon 5 medians"] = Case(
    "time_to_goal", lambda rng, k: np.minimum(rng.lognormal(0.0, 1.0, k), HORIZON),
    *restricted_lognormal(HORIZON))
KEPT = ["normal", "success at rate 0.1", "0/1 count at rate 0.1", "lognormal sigma 0.5",
        "lognormal sigma 1, horizon 5 medians"]


@dataclass(frozen=True)
class Coverage:
    covered: float  # share of batteries whose final interval holds the true mean
    seeds: float  # mean seeds used
    zero_width_stops: int  # stops on an interval of width zero
    unmet: int  # stops at max_seeds short of the target


@cache
def draws(name: str, batteries: int, seed: int, width: int) -> np.ndarray:
    """Row b: battery b's values for seeds 1..width, from its own stream ``[seed, b]``."""
    case = CASES[name]
    return np.stack([case.draw(np.random.default_rng([seed, battery]), width)
                     for battery in range(batteries)])


def stop(row: np.ndarray, rule: UntilRule) -> CellProgress:
    """Where the rule stops a battery whose seeds would give ``row``, all handed over."""
    return cell_progress(dict(enumerate(row.tolist(), start=1)), rule)


def stop_round_by_round(row: np.ndarray, rule: UntilRule) -> CellProgress:
    """The same, each round's values handed over only once the rule has scheduled them."""
    values: dict[int, float] = {}
    while not (progress := cell_progress(values, rule)).complete:
        new = row[len(values):progress.scheduled]  # this round's seeds, and only those
        values.update(zip(range(len(values) + 1, progress.scheduled + 1), new.tolist(),
                          strict=True))
    return progress


def simulate(name: str, rule: UntilRule, batteries: int = BATTERIES,
             seed: int = STREAM) -> Coverage:
    case = CASES[name]
    rows = draws(name, batteries, seed, max(rule.max_seeds, DEFAULT_MAX_SEEDS))
    covered = seeds = zero_width = unmet = 0
    for row in rows:
        progress = stop(row, rule)
        final = row[:progress.scheduled]
        reported = interval_of(final, rule.metric)  # the cell's interval in the reports
        covered += reported.low <= case.mean <= reported.high
        seeds += progress.scheduled
        zero_width += progress.target_met and reported.high == reported.low
        unmet += not progress.target_met
    return Coverage(covered / batteries, seeds / batteries, zero_width, unmet)


def rule_for(name: str, fixed_sample: int, min_seeds: int | None = None) -> UntilRule:
    """The rule whose target a fixed sample of ``fixed_sample`` seeds would just meet."""
    case = CASES[name]
    rule = UntilRule(case.metric, Z * case.sd / math.sqrt(fixed_sample))
    return rule if min_seeds is None else UntilRule(rule.metric, rule.half_width, min_seeds)


@cache
def measured(name: str, fixed_sample: int, min_seeds: int | None = None) -> Coverage:
    """One cell of the coverage table (each simulated once, whichever tests read it)."""
    return simulate(name, rule_for(name, fixed_sample, min_seeds))


@pytest.fixture(autouse=True, scope="module")
def _free_the_draws() -> Iterator[None]:
    yield
    draws.cache_clear()  # about 40 MB, not kept for the rest of the suite
    measured.cache_clear()


@pytest.mark.parametrize("fixed_sample", TARGETS)
@pytest.mark.parametrize("name", KEPT)
def test_final_intervals_cover_the_true_mean(name: str, fixed_sample: int) -> None:
    found = measured(name, fixed_sample)
    assert found.covered >= PROMISED, found
    assert found.zero_width_stops == 0, found
    if fixed_sample <= 100:  # max_seeds 500 is far above what these targets need
        assert found.unmet == 0, found
    assert found.unmet <= 0.01 * BATTERIES, found


@pytest.mark.parametrize("fixed_sample", [10, 100, 300])
def test_the_normal_case_spends_about_what_a_fixed_sample_would(fixed_sample: int) -> None:
    # no seeds wasted on the easy case: min_seeds 20 at n* = 10, a few percent above n*
    # beyond (a sample's spread is an estimate; the rule stops once it says enough)
    found = measured("normal", fixed_sample)
    assert found.seeds <= max(20.5, 1.1 * fixed_sample), found


@pytest.mark.parametrize(("fixed_sample", "floor"), [(10, 0.91), (30, 0.90), (100, 0.87),
                                                     (300, 0.88)])
def test_a_strongly_skewed_metric_keeps_most_of_its_coverage(fixed_sample: int,
                                                             floor: float) -> None:
    # lognormal sigma 1 (skewness 6.2): the measured figures (until.py) less about 1.5
    # points, so that a change of rule or interval that loses coverage here is seen
    found = measured("lognormal sigma 1", fixed_sample)
    assert found.covered >= floor, found
    assert found.zero_width_stops == 0, found


@pytest.mark.xfail(strict=True, reason="a lognormal with sigma 1 under the default rule: "
                   "cells that stop before meeting the long tail, and the printed interval "
                   "itself at 20-40 seeds (92.3-93.0% on fixed samples), stay under 93%: see "
                   "until.py")
@pytest.mark.parametrize("fixed_sample", TARGETS)
def test_a_strongly_skewed_metric_is_the_documented_limit(fixed_sample: int) -> None:
    assert measured("lognormal sigma 1", fixed_sample).covered >= PROMISED


@pytest.mark.parametrize("fixed_sample", TARGETS)
def test_a_strongly_skewed_metric_keeps_the_promise_with_the_documented_minimum(
        fixed_sample: int) -> None:
    # the remedy the docs give: min_seeds = 200 for such a metric, whatever the target
    # (the printed interval's own coverage on fixed samples of it passes 93.5% near 100)
    found = measured("lognormal sigma 1", fixed_sample, 200)
    assert found.covered >= PROMISED, found
    assert found.zero_width_stops == 0, found


def test_the_simulation_measures_a_fixed_sample_exactly() -> None:
    """The harness against hand computation: five seeds, no choice (min = max = 5), of a
    0/1 count at rate 0.1. Its skewness-corrected interval holds 0.1 with 1 to 4 ones
    ([-0.120, 1.549], [-0.150, 1.441], [-0.441, 1.150], [-0.549, 1.120], by root finding
    in test_skew_corrected_interval.py) and misses with 0 or 5 (no spread: a point
    interval): binomial odds 40.95%."""
    from scipy.stats import binom

    name = "0/1 count at rate 0.1"
    found = simulate(name, UntilRule(CASES[name].metric, 0.01, min_seeds=5, max_seeds=5),
                     1000, seed=5)
    for ones, (low, high) in {1: (-0.120, 1.549), 4: (-0.549, 1.120)}.items():
        reported = interval_of(np.array([1.0] * ones + [0.0] * (5 - ones)), CASES[name].metric)
        assert (reported.low, reported.high) == pytest.approx((low, high), abs=5e-4)
    truth = float(binom.pmf([1, 2, 3, 4], 5, 0.1).sum())
    assert truth == pytest.approx(0.40950, abs=1e-5)
    assert abs(found.covered - truth) < 3 * math.sqrt(truth * (1 - truth) / 1000)
    assert found.seeds == 5 and found.unmet == 1000


def test_round_by_round_draws_are_the_shared_rows() -> None:
    # the premise of sharing one draw per case: NumPy's stream gives the same values in
    # rounds of any size as in one call, so each battery is the one a lazy draw would give
    for name in ("normal", "0/1 count at rate 0.1", "lognormal sigma 1"):
        stream = np.random.default_rng([STREAM, 3])
        rounds = np.concatenate([CASES[name].draw(stream, k) for k in (20, 17, 3, 60)])
        assert np.array_equal(rounds, draws(name, BATTERIES, STREAM, DEFAULT_MAX_SEEDS)[3, :100])


@pytest.mark.parametrize(("name", "fixed_sample"), [("normal", 300), ("0/1 count at rate 0.1", 10),
                                                    ("lognormal sigma 1", 100)])
def test_the_rule_handed_every_value_stops_where_a_running_battery_would(
        name: str, fixed_sample: int) -> None:
    rule = rule_for(name, fixed_sample)
    for row in draws(name, BATTERIES, STREAM, DEFAULT_MAX_SEEDS)[:100]:
        assert stop(row, rule) == stop_round_by_round(row, rule)


def test_the_restricted_lognormal_moments_are_those_of_numerical_integration() -> None:
    from scipy import integrate
    from scipy.stats import lognorm

    law = lognorm(1.0)
    below = integrate.quad(lambda x: x * law.pdf(x), 0, HORIZON)[0]
    below_square = integrate.quad(lambda x: x * x * law.pdf(x), 0, HORIZON)[0]
    mean = below + HORIZON * law.sf(HORIZON)
    sd = math.sqrt(below_square + HORIZON ** 2 * law.sf(HORIZON) - mean ** 2)
    assert restricted_lognormal(HORIZON) == pytest.approx((mean, sd), rel=1e-7)
