"""A battery's evidence as tables: intervals per cell, paired comparisons, identical seeds.

Functions of the per-run table (:func:`mimics.batteries.report.runs_table`,
which carries one column per metric of :data:`~mimics.batteries.metrics.METRICS`),
returning DataFrames or lines; no printing. Used by ``mimics battery report``
and ``compare`` and by the workbench.

- :func:`cell_intervals`: per algorithm x scenario x parameter point, each
  metric's mean with its 95% t interval (a proportion with its Wilson interval);
- :func:`paired_comparison`: each algorithm against a baseline on the same
  scenario, parameters and seed: the mean paired difference, its 95% t
  interval, the Wilcoxon signed-rank p-value and the number of pairs;
- :func:`identical_seed_warnings`: cells where two or more seeds gave identical runs.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pandas as pd

from mimics.batteries.metrics import DEFAULT_COMPARED, METRICS
from mimics.batteries.stats import paired_difference, proportion_interval, t_interval
from mimics.world.errors import MimicsError

CELL = ["algorithm", "scenario", "parameters"]
#: Columns of the paired-comparison table (and its CSV), in order.
COMPARISON_COLUMNS = ("algorithm", "baseline", "scenario", "parameters", "metric", "pairs",
                      "mean_difference", "ci95_low", "ci95_high", "p_value", "note")


def check_metrics(metrics: list[str] | tuple[str, ...] | None, where: str = "--metric"
                  ) -> list[str]:
    """The metrics asked for (the default set when none).

    Raises:
        MimicsError: naming ``where`` and the known metrics, for an unknown one.
    """
    for name in metrics or ():
        if name not in METRICS:
            raise MimicsError(f"{where} {name!r}: unknown metric (expected one of: "
                              f"{', '.join(METRICS)})")
    return list(metrics or DEFAULT_COMPARED)


def interval_of(values: np.ndarray, metric: str) -> tuple[float, float, float, int]:
    """(estimate, low, high, n) of one metric's values: Wilson or t, as the metric asks."""
    found = proportion_interval(values) if METRICS[metric].proportion else t_interval(values)
    return found.estimate, found.low, found.high, found.n


def cell_intervals(table: pd.DataFrame, metrics: list[str] | None = None) -> pd.DataFrame:
    """One row per cell: runs, done, and for each metric ``M``, ``M``, ``M_low``,
    ``M_high`` and ``M_n`` (the values it rests on: done runs where it is defined)."""
    rows = []
    for (algorithm, scenario, label), group in table.groupby(CELL, sort=False):
        done = group[group["state"] == "done"]
        row: dict[str, Any] = {"algorithm": algorithm, "scenario": scenario,
                               "parameters": label, "runs": len(group), "done": len(done)}
        for metric in check_metrics(metrics):
            values = done[metric].to_numpy(dtype=float)
            estimate, low, high, n = interval_of(values, metric)
            row.update({metric: estimate, f"{metric}_low": low, f"{metric}_high": high,
                        f"{metric}_n": n})
        rows.append(row)
    return pd.DataFrame(rows)


def paired_comparison(table: pd.DataFrame, baseline: str | None = None,
                      metrics: list[str] | None = None) -> pd.DataFrame:
    """Each algorithm minus the baseline, paired by scenario, parameters and seed.

    Args:
        table: the per-run table.
        baseline: an algorithm of the battery (default: its first).
        metrics: metric names (default: :data:`~mimics.batteries.metrics.DEFAULT_COMPARED`).

    Returns:
        One row per algorithm x scenario x parameter point x metric, with the columns
        of :data:`COMPARISON_COLUMNS` (empty with a single algorithm).

    Raises:
        MimicsError: for an unknown baseline or metric.
    """
    chosen = check_metrics(metrics)
    algorithms = list(dict.fromkeys(table["algorithm"])) if not table.empty else []
    if baseline is None:
        baseline = algorithms[0] if algorithms else ""
    elif baseline not in algorithms:
        raise MimicsError(f"--baseline {baseline!r}: not an algorithm of this battery "
                          f"(expected one of: {', '.join(algorithms)})")
    rows = []
    done = table[table["state"] == "done"] if not table.empty else table
    base = done[done["algorithm"] == baseline]
    for algorithm in algorithms:
        if algorithm == baseline:
            continue
        mine = done[done["algorithm"] == algorithm]
        for (scenario, label), group in mine.groupby(["scenario", "parameters"], sort=False):
            theirs = base[(base["scenario"] == scenario) & (base["parameters"] == label)]
            pairs = group.merge(theirs, on="seed", suffixes=("", "_base"))
            for metric in chosen:
                mine_values = pairs[metric].to_numpy(dtype=float)
                base_values = pairs[f"{metric}_base"].to_numpy(dtype=float)
                result = paired_difference(mine_values, base_values)
                p_value, note = _independence(pairs, mine_values, base_values, result.p_value,
                                              result.note)
                rows.append({"algorithm": algorithm, "baseline": baseline,
                             "scenario": scenario, "parameters": label, "metric": metric,
                             "pairs": result.interval.n,
                             "mean_difference": result.interval.estimate,
                             "ci95_low": result.interval.low, "ci95_high": result.interval.high,
                             "p_value": math.nan if p_value is None else p_value,
                             "note": note})
    return pd.DataFrame(rows, columns=list(COMPARISON_COLUMNS))


def _independence(pairs: pd.DataFrame, mine: np.ndarray, base: np.ndarray,
                  p_value: float | None, note: str) -> tuple[float | None, str]:
    """The p-value and note, checked against copies: a signed-rank test assumes independent
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


def seed_ranges(seeds: list[int]) -> str:
    """``[1, 2, 3, 7]`` -> ``"1-3, 7"``."""
    ordered = sorted(seeds)
    parts: list[str] = []
    start = previous = ordered[0]
    for seed in [*ordered[1:], None]:
        if seed is not None and seed == previous + 1:
            previous = seed
            continue
        parts.append(str(start) if start == previous else f"{start}-{previous}")
        if seed is not None:
            start = previous = seed
    return ", ".join(parts)


def identical_seed_warnings(table: pd.DataFrame, hints: dict[str, str] | None = None
                            ) -> list[str]:
    """One line per cell where two or more seeds gave identical runs (same digest).

    Args:
        table: the per-run table (its ``digest`` column: see
            :func:`mimics.batteries.metrics.run_digest`).
        hints: scenario name -> what to randomize in it (default: start poses or noise).
    """
    if table.empty or "digest" not in table.columns:
        return []
    lines = []
    done = table[(table["state"] == "done") & table["digest"].notna()]
    for (algorithm, scenario, label), group in done.groupby(CELL, sort=False):
        for digest, same in group.groupby("digest", sort=False):
            if len(same) < 2:
                continue
            seeds = [int(s) for s in same["seed"]]
            what = "runs" if str(digest).startswith("t:") else "outcomes"
            cell = f"{algorithm} x {scenario}" + (f" ({label})" if label else "")
            alone = len(same) == len(group)
            hint = (hints or {}).get(scenario) or ("randomize start poses or turn sensor noise "
                                                   "on")
            lines.append(f"seeds {seed_ranges(seeds)} of {cell} gave identical {what}: "
                         + ("the seed changes nothing here" if alone else
                            f"{len(same)} of {len(group)} seeds are copies of one run")
                         + f"; {hint}")
    return lines


def randomize_hints(table: pd.DataFrame) -> dict[str, str]:
    """What to randomize in each scenario of the table: a parameter whose name says it
    randomizes (``random_*``, ``*jitter*``, ``noise``) when the scenario has one."""
    from mimics.catalog import scenario_parameters

    hints = {}
    for scenario, ref in table.drop_duplicates("scenario")[["scenario", "scenario_ref"]].to_numpy(
            ):
        try:
            names = list(scenario_parameters(ref)) if not str(ref).endswith(".toml") else []
        except MimicsError:
            names = []
        knobs = [n for n in names if n.startswith("random") or "jitter" in n or "noise" in n]
        if knobs:
            hints[scenario] = (f"randomize start poses ({', '.join(knobs)}) or turn sensor noise"
                               " on")
    return hints
