"""The stopping rule keeps its promise: simulated batteries whose reported 95% interval, at
the cell's stop, covers the true mean at least 93% of the time.

Each simulated battery is one cell fed by the project's own :func:`cell_progress`: the
values of each round are drawn lazily from the battery's own seeded stream, only when
the rule schedules those seeds, and the interval checked is the one the reports print
(:func:`mimics.batteries.comparison.interval_of`). 2,000 batteries per case put the
simulation's own standard error near 0.5 points at 95% coverage.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pytest

from mimics.batteries.comparison import interval_of
from mimics.batteries.until import UntilRule, cell_progress

BATTERIES = 2000
PROMISED = 0.93
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


@dataclass(frozen=True)
class Coverage:
    covered: float  # share of batteries whose final interval holds the true mean
    seeds: float  # mean seeds used
    zero_width_stops: int  # stops on an interval of width zero
    unmet: int  # stops at max_seeds short of the target


def simulate(case: Case, rule: UntilRule, batteries: int, seed: int) -> Coverage:
    covered = seeds = zero_width = unmet = 0
    for battery in range(batteries):
        stream = np.random.default_rng([seed, battery])
        values: dict[int, float] = {}
        while not (progress := cell_progress(values, rule)).complete:
            new = case.draw(stream, progress.scheduled - len(values))  # this round's seeds
            values.update(zip(range(len(values) + 1, progress.scheduled + 1),
                              new.tolist(), strict=True))
        final = np.array([values[s] for s in range(1, progress.scheduled + 1)])
        reported = interval_of(final, rule.metric)  # the cell's interval in the reports
        covered += reported.low <= case.mean <= reported.high
        seeds += progress.scheduled
        zero_width += progress.target_met and reported.high == reported.low
        unmet += not progress.target_met
    return Coverage(covered / batteries, seeds / batteries, zero_width, unmet)


def rule_for(case: Case, fixed_sample: int) -> UntilRule:
    """The rule whose target a fixed sample of ``fixed_sample`` seeds would just meet."""
    return UntilRule(case.metric, Z * case.sd / math.sqrt(fixed_sample))


@pytest.mark.parametrize("fixed_sample", [10, 100])
@pytest.mark.parametrize("name", ["normal", "success at rate 0.1", "0/1 count at rate 0.1",
                                  "lognormal sigma 0.5"])
def test_final_intervals_cover_the_true_mean(name: str, fixed_sample: int) -> None:
    case = CASES[name]
    found = simulate(case, rule_for(case, fixed_sample), BATTERIES, seed=fixed_sample)
    assert found.covered >= PROMISED, found
    assert found.zero_width_stops == 0, found
    assert found.unmet == 0, found  # max_seeds 500 is far above what these targets need


def test_a_strongly_skewed_metric_keeps_most_of_its_coverage() -> None:
    # lognormal sigma 1 (skewness 6.2): the skewness-corrected interval measured 92.5%
    # here; the plain t interval, printed before, 88.8% on the same seeds
    case = CASES["lognormal sigma 1"]
    found = simulate(case, rule_for(case, 10), BATTERIES, seed=10)
    assert found.covered >= 0.91, found
    assert found.zero_width_stops == 0 and found.unmet == 0, found


@pytest.mark.xfail(strict=True, reason="a lognormal with sigma 1 and a target 5 times beyond "
                   "min_seeds: cells that stop at 20-40 seeds have not met the long tail, "
                   "and no interval of their values knows it (87.6%): see until.py")
def test_a_strongly_skewed_metric_is_the_documented_limit() -> None:
    case = CASES["lognormal sigma 1"]
    found = simulate(case, rule_for(case, 100), BATTERIES, seed=100)
    assert found.covered >= PROMISED, found


def test_the_simulation_measures_a_fixed_sample_exactly() -> None:
    """The harness against hand computation: five seeds, no choice (min = max = 5), of a
    0/1 count at rate 0.1. Its skewness-corrected interval holds 0.1 with 1 to 4 ones
    ([-0.120, 1.549], [-0.150, 1.441], [-0.441, 1.150], [-0.549, 1.120], by root finding
    in test_skew_corrected_interval.py) and misses with 0 or 5 (no spread: a point
    interval): binomial odds 40.95%."""
    from scipy.stats import binom

    case = CASES["0/1 count at rate 0.1"]
    found = simulate(case, UntilRule(case.metric, 0.01, min_seeds=5, max_seeds=5), 1000,
                     seed=5)
    for ones, (low, high) in {1: (-0.120, 1.549), 4: (-0.549, 1.120)}.items():
        reported = interval_of(np.array([1.0] * ones + [0.0] * (5 - ones)), case.metric)
        assert (reported.low, reported.high) == pytest.approx((low, high), abs=5e-4)
    truth = float(binom.pmf([1, 2, 3, 4], 5, 0.1).sum())
    assert truth == pytest.approx(0.40950, abs=1e-5)
    assert abs(found.covered - truth) < 3 * math.sqrt(truth * (1 - truth) / 1000)
    assert found.seeds == 5 and found.unmet == 1000
