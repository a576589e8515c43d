"""A battery's evidence as tables: intervals per cell, paired comparisons, failures, costs.

Functions of the per-run table (:func:`mimics.batteries.report.runs_table`,
which carries one column per metric of :data:`~mimics.batteries.metrics.METRICS`),
returning DataFrames or lines; no printing. Used by ``mimics battery report``
and ``compare``, the notebook and the workbench.

- :func:`cell_intervals`: per algorithm x scenario x parameter point, its runs,
  done and failed, and each metric's mean with its 95% interval (Student t
  corrected for the sample's skewness, Hall 1992, or BCa bootstrap on request; a
  proportion with its Wilson interval);
- :func:`paired_comparison`: each algorithm against a baseline on the same
  scenario, parameters and seed: rates by Newcombe's paired interval and
  McNemar's exact test, means by the t interval and the Wilcoxon signed-rank
  test, each p-value also adjusted for the number of tests shown (Holm);
- :func:`failed_runs_lines`: the failed runs of each cell, named;
- :func:`cost_table`: what the runs cost (wall and user-code time), apart from
  what they did.

A failed run (error, time-out, crash) counts: success 0 and reached goal 0
(it brought no robot home), the metrics that need a finished run missing
(their ``n`` says how many values there are). ``exclude_failed`` drops failed
runs on purpose, the old behaviour.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd

from mimics.batteries.metrics import DEFAULT_COMPARED, METRICS
from mimics.batteries.multiplicity import ADJUST_METHODS, adjust_p_values
from mimics.batteries.paired_rates import paired_proportion_difference
from mimics.batteries.seed_warnings import CELL, identical_seed_warnings, seed_ranges
from mimics.batteries.states import FAILED_STATES
from mimics.batteries.stats import (
    Interval,
    bootstrap_interval,
    paired_difference,
    proportion_interval,
    skew_corrected_interval,
)
from mimics.world.errors import MimicsError

__all__ = ["COMPARISON_COLUMNS", "INTERVAL_METHODS", "cell_intervals", "check_metrics",
           "cost_table", "failed_runs_lines", "identical_seed_warnings", "interval_of",
           "metric_values", "paired_comparison", "seed_ranges"]

#: Columns of the paired-comparison table (and its CSV), in order.
COMPARISON_COLUMNS = ("algorithm", "baseline", "scenario", "parameters", "metric", "primary",
                      "pairs", "mean_difference", "ci95_low", "ci95_high", "test", "p_value",
                      "p_adjusted", "note")
#: How a mean's interval is computed.
INTERVAL_METHODS = ("t", "bootstrap")
FINISHED = ("done", *FAILED_STATES)


def check_metrics(metrics: list[str] | tuple[str, ...] | None, where: str = "--metric"
                  ) -> list[str]:
    """The metrics asked for (the default set when none).

    Raises:
        MimicsError: naming ``where`` and the known metrics, for an unknown one.
    """
    for name in metrics or ():
        if not isinstance(name, str) or name not in METRICS:
            raise MimicsError(f"{where} {name!r}: unknown metric (expected one of: "
                              f"{', '.join(METRICS)})")
    return list(metrics or DEFAULT_COMPARED)


def check_choice(value: str, choices: tuple[str, ...], where: str) -> str:
    """``value`` if it is one of ``choices``.

    Raises:
        MimicsError: naming ``where`` and the choices.
    """
    if value not in choices:
        raise MimicsError(f"{where} {value!r}: expected one of {', '.join(choices)}")
    return value


def finished_runs(table: pd.DataFrame, exclude_failed: bool = False) -> pd.DataFrame:
    """The runs that ended: done ones, and failed ones unless ``exclude_failed``."""
    if table.empty:
        return table
    return table[table["state"].isin(("done",) if exclude_failed else FINISHED)]


def metric_values(runs: pd.DataFrame, metric: str) -> np.ndarray:
    """The metric's value of each run (NaN: undefined), failed runs at the metric's
    ``if_failed`` value (success and reached goal 0)."""
    values = np.array(pd.to_numeric(runs[metric], errors="coerce").to_numpy(
        dtype=float, na_value=np.nan))  # a copy: failed runs are written over
    if_failed = METRICS[metric].if_failed
    failed = runs["state"].isin(FAILED_STATES).to_numpy()
    values[failed] = math.nan if if_failed is None else if_failed
    if METRICS[metric].needs_goal and "goal_less" in runs:
        values[runs["goal_less"].to_numpy(dtype=bool)] = math.nan  # n/a, not 0
    return values


def interval_of(values: np.ndarray, metric: str, method: str = "t") -> Interval:
    """One metric's estimate and 95% interval: Wilson for a proportion; for a mean,
    ``"t"`` is the t interval corrected for the sample's skewness (Hall 1992,
    :func:`~mimics.batteries.stats.skew_corrected_interval`: the plain t interval on a
    symmetric sample; the stopping rule uses the same), ``"bootstrap"`` the BCa bootstrap."""
    if METRICS[metric].proportion:
        return proportion_interval(values)
    if method == "bootstrap":
        return bootstrap_interval(values)
    return skew_corrected_interval(values)


def cell_intervals(table: pd.DataFrame, metrics: list[str] | None = None, *,
                   exclude_failed: bool = False, method: str = "t") -> pd.DataFrame:
    """One row per cell: ``runs``, ``done``, ``failed``, and for each metric ``M``: ``M``,
    ``M_low``, ``M_high`` and ``M_n`` (the runs its value rests on)."""
    check_choice(method, INTERVAL_METHODS, "--interval")
    rows = []
    for (algorithm, scenario, label), group in table.groupby(CELL, sort=False):
        ended = finished_runs(group, exclude_failed)
        row: dict[str, Any] = {"algorithm": algorithm, "scenario": scenario,
                               "parameters": label, "runs": len(group),
                               "done": int((group["state"] == "done").sum()),
                               "failed": int(group["state"].isin(FAILED_STATES).sum())}
        for metric in check_metrics(metrics):
            found = interval_of(metric_values(ended, metric), metric, method)
            row.update({metric: found.estimate, f"{metric}_low": found.low,
                        f"{metric}_high": found.high, f"{metric}_n": found.n})
        rows.append(row)
    return pd.DataFrame(rows)


def paired_comparison(table: pd.DataFrame, baseline: str | None = None,
                      metrics: list[str] | None = None, *, exclude_failed: bool = False,
                      adjust: str = "holm", primary: str | None = None,
                      method: str = "t") -> pd.DataFrame:
    """Each algorithm minus the baseline, paired by scenario, parameters and seed.

    Args:
        table: the per-run table.
        baseline: an algorithm of the battery (default: its first).
        metrics: metric names (default: :data:`~mimics.batteries.metrics.DEFAULT_COMPARED`).
        exclude_failed: leave failed runs out (default: they count, as success 0).
        adjust: ``"holm"``, ``"bh"`` or ``"none"``: ``p_adjusted`` over the rows with a p.
        primary: the battery's primary metric (its rows marked).
        method: ``"t"`` or ``"bootstrap"`` for the interval of a mean difference.

    Returns:
        One row per algorithm x scenario x parameter point x metric, with the columns
        of :data:`COMPARISON_COLUMNS` (empty with a single algorithm).

    Raises:
        MimicsError: for an unknown baseline, metric, adjustment or method.
    """
    chosen = check_metrics(metrics)
    check_choice(adjust, ADJUST_METHODS, "--adjust")
    check_choice(method, INTERVAL_METHODS, "--interval")
    algorithms = list(dict.fromkeys(table["algorithm"])) if not table.empty else []
    if baseline is None:
        baseline = algorithms[0] if algorithms else ""
    elif baseline not in algorithms:
        raise MimicsError(f"--baseline {baseline!r}: not an algorithm of this battery "
                          f"(expected one of: {', '.join(algorithms)})")
    rows = []
    ended = finished_runs(table, exclude_failed)
    base = ended[ended["algorithm"] == baseline] if not ended.empty else ended
    for algorithm in algorithms:
        if algorithm == baseline:
            continue
        mine = ended[ended["algorithm"] == algorithm]
        for (scenario, label), group in mine.groupby(["scenario", "parameters"], sort=False):
            theirs = base[(base["scenario"] == scenario) & (base["parameters"] == label)]
            pairs = group.merge(theirs, on="seed", suffixes=("", "_base"))
            base_side = pairs[[c for c in pairs.columns if c.endswith("_base")]].rename(
                columns=lambda c: c[:-len("_base")])  # the baseline's runs, as a runs table
            for metric in chosen:
                rows.append({"algorithm": algorithm, "baseline": baseline,
                             "scenario": scenario, "parameters": label, "metric": metric,
                             "primary": metric == primary,
                             **_compare_metric(pairs, base_side, metric, method)})
    frame = pd.DataFrame(rows, columns=list(COMPARISON_COLUMNS))
    if not frame.empty:
        frame["p_adjusted"] = adjust_p_values(frame["p_value"].to_numpy(dtype=float), adjust)
    return frame


def _compare_metric(pairs: pd.DataFrame, base_side: pd.DataFrame, metric: str,
                    method: str) -> dict[str, Any]:
    """The difference of one metric over the pairs (``base_side``: their baseline runs):
    interval, test, p-value and note."""
    mine = metric_values(pairs, metric)
    theirs = metric_values(base_side, metric)
    if METRICS[metric].proportion:
        result, test = paired_proportion_difference(mine, theirs), "McNemar exact"
    else:
        result, test = paired_difference(mine, theirs), "Wilcoxon signed-rank"
        if method == "bootstrap":
            keep = ~(np.isnan(mine) | np.isnan(theirs))
            result = type(result)(bootstrap_interval(mine[keep] - theirs[keep]), result.p_value,
                                  result.note)
    p_value, note = _independence(pairs, mine, theirs, result.p_value, result.note)
    interval = result.interval
    notes = [note] if note else []
    if METRICS[metric].conditional:
        notes.insert(0, f"conditional: only the {interval.n} of {len(pairs)} pairs where both "
                        f"runs had {METRICS[metric].conditional}")
    elif interval.n < len(pairs):
        notes.insert(0, f"{len(pairs) - interval.n} of {len(pairs)} pairs without a value "
                        "(failed runs, or no robot with a goal)")
    if (interval.n >= 2 and interval.low == interval.high and not METRICS[metric].proportion
            and interval.estimate != 0):  # the test's note already says "all zero"
        notes.append(f"all {interval.n} differences are {interval.estimate:g}: no spread, no "
                     "interval")
    return {"pairs": interval.n, "mean_difference": interval.estimate, "ci95_low": interval.low,
            "ci95_high": interval.high, "test": test if p_value is not None else "",
            "p_value": math.nan if p_value is None else p_value, "p_adjusted": math.nan,
            "note": "; ".join(notes)}


def _independence(pairs: pd.DataFrame, mine: np.ndarray, base: np.ndarray,
                  p_value: float | None, note: str) -> tuple[float | None, str]:
    """The p-value and note, checked against copies: a paired test assumes independent
    pairs, and seeds that change nothing give the same pair again and again."""
    if "digest" not in pairs.columns or p_value is None:
        return p_value, note
    used = pairs[~(np.isnan(mine) | np.isnan(base))]
    if used["digest"].isna().any() or used["digest_base"].isna().any():
        return p_value, note
    distinct = len(used.drop_duplicates(["digest", "digest_base"]))
    if distinct == 1:
        return None, (f"all {len(used)} pairs are copies of one pair of runs (the seed changes "
                      "nothing): one observation, no p-value")
    if distinct < len(used):
        return p_value, (f"only {distinct} distinct pairs of runs among {len(used)}: the "
                         "p-value assumes independent pairs and overstates the evidence")
    return p_value, note


def failed_runs_lines(table: pd.DataFrame) -> list[str]:
    """One line per cell with failed runs: how many, their seeds and states."""
    lines = []
    if table.empty:
        return lines
    for (algorithm, scenario, label), group in table.groupby(CELL, sort=False):
        failed = group[group["state"].isin(FAILED_STATES)]
        if failed.empty:
            continue
        states = ", ".join(f"{state} {count}" for state, count in
                           failed["state"].value_counts().items())
        cell = f"{algorithm} x {scenario}" + (f" ({label})" if label else "")
        lines.append(f"{cell}: {len(failed)} of {len(group)} runs failed ({states}), seeds "
                     f"{seed_ranges([int(s) for s in failed['seed']])}")
    return lines


def cost_table(table: pd.DataFrame) -> pd.DataFrame:
    """Per cell, what its done runs cost: mean and total wall time, mean user-code time."""
    rows = []
    for (algorithm, scenario, label), group in table.groupby(CELL, sort=False):
        done = group[group["state"] == "done"]
        wall = pd.to_numeric(done["wall_time"], errors="coerce").dropna()
        user = (pd.to_numeric(done["user_time"], errors="coerce").dropna()
                if "user_time" in done else pd.Series(dtype=float))
        rows.append({"algorithm": algorithm, "scenario": scenario, "parameters": label,
                     "done": len(done), "wall_time_mean": wall.mean() if len(wall) else math.nan,
                     "wall_time_total": float(wall.sum()),
                     "user_time_mean": user.mean() if len(user) else math.nan})
    return pd.DataFrame(rows)
