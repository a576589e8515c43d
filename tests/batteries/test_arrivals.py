"""Arrival curves: the Kaplan-Meier fraction of goal robots arrived, against truths
computed here (the product-limit formula and Greenwood's variance written out, the
plain empirical CDF, SciPy's ecdf on an uncensored sample)."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from mimics.batteries.arrivals import arrival_curve, arrival_curves
from mimics.world.errors import MimicsError


def product_limit(arrivals: list[float], censored: list[float]
                  ) -> dict[float, tuple[float, float, float]]:
    """By hand: at each arrival time t, F(t) = 1 - prod(1 - d/n) over arrival times <= t
    (n robots still observed just before, d arriving then), with Greenwood's 95% interval
    F +- 1.96 * S * sqrt(sum d / (n (n - d))), clipped to [0, 1] (NaN where n == d)."""
    everyone = [(t, True) for t in arrivals] + [(t, False) for t in censored]
    survival, greenwood, out = 1.0, 0.0, {}
    for t in sorted(set(arrivals)):
        at_risk = sum(1 for s, _ in everyone if s >= t)
        d = sum(1 for s, arrived in everyone if arrived and s == t)
        survival *= 1 - d / at_risk
        greenwood = greenwood + d / (at_risk * (at_risk - d)) if at_risk > d else math.nan
        half = 1.959963984540054 * survival * math.sqrt(greenwood)
        fraction = 1 - survival
        out[t] = (fraction, max(fraction - half, 0.0), min(fraction + half, 1.0))
    return out


def value_at(curve, t: float) -> int:
    """Index of the step holding time t (the curve is right-continuous)."""
    return int(np.searchsorted(curve.times, t, side="right")) - 1


def test_the_curve_is_the_product_limit_estimate_with_greenwoods_interval() -> None:
    # three runs of 4 goal robots, 60 s horizon; a tie at 12 s across runs
    times = [[5.0, 12.0, 30.0], [12.0, 41.5], [8.0, 12.0, 20.0, 59.0]]
    curve = arrival_curve(times, [4, 4, 4], [60.0] * 3)
    truth = product_limit([t for run in times for t in run], [60.0] * 3)
    assert (curve.robots, curve.arrived, curve.runs, curve.horizon) == (12, 9, 3, 60.0)
    for t, (fraction, low, high) in truth.items():
        k = value_at(curve, t)
        assert curve.fraction[k] == pytest.approx(fraction, abs=1e-12)
        assert curve.low[k] == pytest.approx(low, abs=1e-9)
        assert curve.high[k] == pytest.approx(high, abs=1e-9)
    assert curve.fraction[-1] == pytest.approx(9 / 12)  # one horizon: arrived / robots
    assert np.all(np.diff(curve.fraction) >= 0)


def test_without_censoring_the_curve_is_the_empirical_cdf() -> None:
    sample = [3.0, 7.5, 7.5, 9.0, 14.0, 2.0]
    curve = arrival_curve([sample[:2], sample[2:]], [2, 4], [20.0, 20.0])
    plain = [np.mean(np.array(sample) <= t) for t in curve.times]
    assert curve.fraction == pytest.approx(plain, abs=1e-12)
    scipy_cdf = stats.ecdf(sample).cdf
    assert curve.times.tolist() == scipy_cdf.quantiles.tolist()
    assert curve.fraction == pytest.approx(scipy_cdf.probabilities, abs=1e-12)
    assert curve.fraction[-1] == 1.0 and curve.arrived == curve.robots == 6


def test_runs_with_different_horizons_censor_their_robots_at_their_own() -> None:
    # run A (30 s): 2 of 3 arrive; run B (60 s): 2 of 3 arrive, one after A's horizon
    curve = arrival_curve([[10.0, 25.0], [20.0, 45.0]], [3, 3], [30.0, 60.0])
    truth = product_limit([10.0, 25.0, 20.0, 45.0], [30.0, 60.0])
    # by hand: 1/6; 1 - 5/6*4/5 = 1/3; 1 - 2/3*3/4 = 1/2; 1 - 1/2*1/2 = 3/4 (2 still
    # observed at 45 s: run A's robot left the risk set at 30 s)
    assert [truth[t][0] for t in (10.0, 20.0, 25.0, 45.0)] == pytest.approx([1 / 6, 1 / 3,
                                                                               1 / 2, 3 / 4])
    for t, (fraction, _, _) in truth.items():
        assert curve.fraction[value_at(curve, t)] == pytest.approx(fraction, abs=1e-12)
    assert curve.fraction[-1] == pytest.approx(0.75)  # not the naive arrived / robots, 4/6
    assert curve.horizon == 60.0 and curve.times[-1] == 60.0


def test_no_goal_robots_give_an_empty_curve() -> None:
    curve = arrival_curve([[], []], [0, 0], [60.0, 60.0])
    assert (curve.robots, curve.arrived, curve.runs, curve.horizon) == (0, 0, 2, 60.0)
    assert curve.times.size == curve.fraction.size == curve.low.size == 0
    nobody = arrival_curve([[], []], [2, 1], [60.0, 30.0])  # goal robots, none arrived
    assert nobody.robots == 3 and nobody.arrived == 0
    assert np.all(nobody.fraction == 0) and np.all(np.isnan(nobody.low))


@pytest.mark.parametrize(("times", "goals", "horizons", "message"), [
    ([[1.0]], [1, 2], [60.0], "one entry per run"),
    ([[1.0, 2.0]], [1], [60.0], "2 arrival times for 1 goal robot"),
    ([[61.0]], [1], [60.0], "after the run's 60 s horizon"),
    ([[1.0]], [1], [math.nan], "horizon must be a positive"),
    ([[-1.0]], [1], [60.0], "finite and 0 or more"),
])
def test_bad_input_is_one_clear_error(times, goals, horizons, message) -> None:
    with pytest.raises(MimicsError, match=message):
        arrival_curve(times, goals, horizons)


runs_strategy = st.lists(st.tuples(st.integers(0, 5), st.lists(
    st.floats(0.0, 60.0, allow_nan=False), max_size=5)), min_size=1, max_size=6)


@settings(max_examples=60, deadline=None)
@given(runs=runs_strategy)
def test_with_one_horizon_the_curve_counts_arrivals_by_t(runs) -> None:
    """Censoring only at the common horizon: F(t) is exactly arrivals by t over robots."""
    times = [arrivals[:goals] for goals, arrivals in runs]
    goals = [max(goals, len(arrivals)) for goals, arrivals in runs]
    curve = arrival_curve(times, goals, [60.0] * len(runs))
    every = np.array([t for run in times for t in run])
    assert curve.robots == sum(goals) and curve.arrived == every.size
    for t, fraction in zip(curve.times, curve.fraction, strict=True):
        assert fraction == pytest.approx(np.sum(every <= t) / curve.robots, abs=1e-12)
    finite = np.isfinite(curve.low)
    assert np.all(curve.low[finite] <= curve.fraction[finite] + 1e-12)
    assert np.all(curve.fraction[finite] <= curve.high[finite] + 1e-12)


def runs_table() -> pd.DataFrame:
    """A runs table as ``mimics.batteries.report.runs_table`` gives it (the columns read)."""
    rows = [("a", "done", [10.0, 20.0], 2, 60.0), ("a", "done", [30.0], 2, 60.0),
            ("a", "error", None, pd.NA, math.nan),       # failed: no outcome
            ("a", "done", None, pd.NA, math.nan),        # an older battery's run: no record
            ("b", "done", [], 2, 60.0), ("b", "done", [5.0], 2, math.nan)]  # no time limit
    return pd.DataFrame({
        "algorithm": [r[0] for r in rows], "scenario": "line", "parameters": "robots=2",
        "seed": range(len(rows)), "state": [r[1] for r in rows],
        "arrival_times": [r[2] for r in rows],
        "goal_robots": pd.array([r[3] for r in rows], dtype="Int64"),
        "horizon": [r[4] for r in rows], "sim_time": [60.0, 60.0, math.nan, 60.0, 60.0, 40.0]})


def test_arrival_curves_take_the_done_runs_with_a_record_per_cell() -> None:
    curves = arrival_curves(runs_table())
    assert list(curves) == [("a", "line", "robots=2"), ("b", "line", "robots=2")]
    a, b = curves.values()
    assert (a.runs, a.robots, a.arrived) == (2, 4, 3)
    assert a.fraction.tolist() == pytest.approx(
        arrival_curve([[10.0, 20.0], [30.0]], [2, 2], [60.0, 60.0]).fraction.tolist())
    # b's second run had no time limit: its robot that never arrived is censored at 40 s
    assert (b.runs, b.robots, b.arrived) == (2, 4, 1)
    assert b.times.tolist() == [5.0, 40.0, 60.0] and b.fraction[0] == pytest.approx(0.25)


def test_arrival_curves_of_an_older_table_are_none() -> None:
    older = runs_table().drop(columns=["arrival_times", "goal_robots", "horizon"])
    assert arrival_curves(older) == {}
    assert arrival_curves(runs_table().iloc[0:0]) == {}
    with pytest.raises(MimicsError, match="no parameters column"):
        arrival_curves(older.drop(columns=["parameters"]))
