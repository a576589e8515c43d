"""Arrival curves: the fraction of goal robots arrived by time t (Kaplan-Meier).

Every robot with a goal counts. A robot that arrived is an event at its
arrival time; one that never arrived (deactivated, deadlocked, still on its
way) is right-censored at its run's horizon (the run's time limit): all we
know is that it had not arrived by then. The Kaplan-Meier estimate over all
goal robots of a cell's runs is then the fraction arrived by each time, with
SciPy's pointwise 95% interval (Greenwood's formula) where it is defined.

>>> curve = arrival_curve([[10.0, 20.0], [30.0]], [2, 2], [60.0, 60.0])
>>> curve.times.tolist(), curve.fraction.tolist()
([10.0, 20.0, 30.0, 60.0], [0.25, 0.5, 0.75, 0.75])
>>> (curve.robots, curve.arrived, curve.runs, curve.horizon)
(4, 3, 2, 60.0)
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from mimics.batteries.metrics import is_missing
from mimics.world.errors import MimicsError

#: The columns of a runs table that :func:`arrival_curves` reads.
CELL = ("algorithm", "scenario", "parameters")


@dataclass(frozen=True)
class ArrivalCurve:
    """A Kaplan-Meier arrival curve, a step function right-continuous at ``times``.

    Attributes:
        times: the distinct arrival and censoring times (s), increasing.
        fraction: the estimated fraction of goal robots arrived by each of ``times``
            (0 before the first).
        low, high: its pointwise 95% interval (NaN where Greenwood's formula is undefined,
            e.g. where every robot still observed has arrived).
        robots: goal robots over all runs; runs: runs; arrived: robots that arrived.
        horizon: the latest horizon of the runs (s), NaN without runs.
    """

    times: np.ndarray
    fraction: np.ndarray
    low: np.ndarray
    high: np.ndarray
    robots: int
    runs: int
    horizon: float
    arrived: int


def arrival_curve(arrival_times: Sequence[Sequence[float]], goal_robots: Sequence[int],
                  horizons: Sequence[float]) -> ArrivalCurve:
    """The Kaplan-Meier fraction of goal robots arrived by time t, over runs.

    Args:
        arrival_times: per run, the arrival times (s) of its robots that arrived.
        goal_robots: per run, its robots with a goal (arrived or not).
        horizons: per run, its horizon (s): each robot that did not arrive is censored there.

    Returns:
        The curve; with no goal robot at all an empty one (no times, ``robots`` 0).

    Raises:
        MimicsError: lists of different lengths, more arrivals than goal robots, a negative
            or non-finite time, an arrival after its run's horizon, or a bad horizon.
    """
    if not len(arrival_times) == len(goal_robots) == len(horizons):
        raise MimicsError(f"arrival_curve: expected one entry per run in arrival_times, "
                          f"goal_robots and horizons, got {len(arrival_times)}, "
                          f"{len(goal_robots)} and {len(horizons)}")
    arrived: list[np.ndarray] = []
    censored: list[np.ndarray] = []
    for run, (times, goals, horizon) in enumerate(zip(arrival_times, goal_robots, horizons,
                                                      strict=True)):
        values = np.asarray(times, dtype=np.float64).reshape(-1)
        _check_run(run, values, int(goals), float(horizon))
        arrived.append(values)
        censored.append(np.full(int(goals) - values.size, float(horizon)))
        # a run without goal robots adds nothing, but still counts as a run
    events = np.concatenate(arrived) if arrived else np.zeros(0)
    right = np.concatenate(censored) if censored else np.zeros(0)
    runs = len(goal_robots)
    horizon = max((float(h) for h in horizons), default=math.nan)
    if events.size + right.size == 0:
        empty = np.zeros(0)
        return ArrivalCurve(empty, empty, empty, empty, 0, runs, horizon, 0)
    return _kaplan_meier(events, right, runs, horizon)


def _check_run(run: int, times: np.ndarray, goals: int, horizon: float) -> None:
    where = f"arrival_curve: run {run}"
    if goals < 0:
        raise MimicsError(f"{where}: goal_robots must be 0 or more, got {goals}")
    if times.size > goals:
        raise MimicsError(f"{where}: {times.size} arrival times for {goals} goal robot(s); "
                          "expected at most one per goal robot")
    if not (math.isfinite(horizon) and horizon > 0):
        raise MimicsError(f"{where}: horizon must be a positive number of seconds, "
                          f"got {horizon}")
    if times.size and not (np.isfinite(times).all() and times.min() >= 0):
        raise MimicsError(f"{where}: arrival times must be finite and 0 or more")
    if times.size and times.max() > horizon:
        raise MimicsError(f"{where}: an arrival at {times.max():g} s, after the run's "
                          f"{horizon:g} s horizon")


def _kaplan_meier(events: np.ndarray, right: np.ndarray, runs: int,
                  horizon: float) -> ArrivalCurve:
    from scipy.stats import CensoredData, ecdf

    cdf = ecdf(CensoredData(uncensored=events, right=right)).cdf
    fraction = np.asarray(cdf.probabilities, dtype=np.float64)
    low = np.full_like(fraction, np.nan)
    high = np.full_like(fraction, np.nan)
    if events.size:  # without any arrival the curve is 0 throughout: no interval to draw
        with warnings.catch_warnings():  # "undefined at some observations": left as NaN
            warnings.simplefilter("ignore", RuntimeWarning)
            interval = cdf.confidence_interval(0.95)
        low = np.asarray(interval.low.probabilities, dtype=np.float64)
        high = np.asarray(interval.high.probabilities, dtype=np.float64)
    return ArrivalCurve(np.asarray(cdf.quantiles, dtype=np.float64), fraction, low, high,
                        robots=int(events.size + right.size), runs=runs, horizon=horizon,
                        arrived=int(events.size))


def arrival_curves(table: pd.DataFrame) -> dict[tuple[str, str, str], ArrivalCurve]:
    """One arrival curve per algorithm x scenario x parameter point of a runs table.

    Over the ``done`` runs with an arrival record (``arrival_times`` not None: runs of
    older batteries have none and are left out); each non-arrival is censored at its
    run's ``horizon``, or at its ``sim_time`` when the run had no time limit. Cells
    without such a run have no curve. Keys are in the table's order.

    Raises:
        MimicsError: a table without the columns of a runs table.
    """
    missing = [c for c in (*CELL, "state") if c not in table.columns]
    if missing:
        raise MimicsError(f"arrival_curves: the table has no {', '.join(missing)} column: "
                          "expected a battery's runs table")
    if table.empty or "arrival_times" not in table.columns:
        return {}
    done = table[table["state"] == "done"]
    curves: dict[tuple[str, str, str], ArrivalCurve] = {}
    for key, cell in done.groupby(list(CELL), sort=False):
        times, goals, horizons = [], [], []
        for row in cell.to_dict("records"):
            record = run_record(row)
            if record is not None:
                times.append(record[0])
                goals.append(record[1])
                horizons.append(record[2])
        if goals:
            curves[(str(key[0]), str(key[1]), str(key[2]))] = arrival_curve(times, goals,
                                                                           horizons)
    return curves


def run_record(row: dict[str, Any]) -> tuple[list[float], int, float] | None:
    """A run's arrival times, goal robots and censoring time, or None without a record."""
    times = row.get("arrival_times")
    goals = row.get("goal_robots")
    if times is None or isinstance(times, float) or is_missing(goals):  # NaN: no record
        return None
    goals = int(goals)
    horizon = _number(row.get("horizon"))
    if not math.isfinite(horizon):  # no time limit: observed until the run ended
        horizon = _number(row.get("sim_time"))
    if not math.isfinite(horizon):
        if goals > len(times):  # non-arrivals with nowhere to censor them
            return None
        horizon = max([*times, 1e-9])
    return [float(t) for t in times], goals, horizon


def _number(value: Any) -> float:
    return math.nan if is_missing(value) else float(value)
