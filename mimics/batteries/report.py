"""The top-tier table of a battery (paper section 3.8), its aggregates and exports.

One row per run: algorithm, scenario, parameters, seed, state, robots that
reached their goal, collisions, deadlocks, livelocks, escapes, exceptions and
duration; a run that misbehaved (not ``done``, or with any collision,
deadlock, livelock, escape or exception) is marked, so that it is found at a
glance. The aggregate has one row per algorithm x scenario (x parameter
point): run counts by outcome and the mean of each count over the ``done``
runs with its 95% confidence interval (Student's t).

Everything is read from ``battery.db``; a battery still running can be
reported on.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from rich.console import Console
from rich.table import Table

from mimics.batteries.metrics import SUMMARY_STATS, row_value
from mimics.batteries.store import RUNS_DIR, BatteryStore
from mimics.batteries.tasks import COUNTS, FAILED_STATES
from mimics.world.errors import MimicsError

#: Counts that mark a run as misbehaving when above zero.
TROUBLE = ("collisions", "deadlocks", "livelocks", "escaped", "exceptions")
#: Per-run metrics averaged in the aggregate.
METRICS = ("reached_goal", "collisions", "deadlocks", "livelocks", "escaped", "exceptions",
           "wall_time")
#: Columns of the CSV/Parquet export, in order (``param_NAME`` columns follow ``parameters``).
EXPORT_COLUMNS = ("id", "algorithm", "scenario", "parameters", "seed", "state", "misbehaving",
                  "status", *COUNTS, "success", *SUMMARY_STATS, "sim_time", "wall_time",
                  "digest", "attempts", "worker", "started", "ended", "error", "folder")


def runs_table(folder: str | Path) -> pd.DataFrame:
    """One row per run of a battery, from its database.

    Columns: those of :data:`EXPORT_COLUMNS` plus ``param_NAME`` for each
    scenario parameter of the battery file, ``params`` (JSON), ``label``
    and ``traceback``. Counts are nullable integers (empty for runs without
    an outcome: pending, running, killed, crashed). ``success`` (1.0 when every
    robot reached its goal) and the summary's per-robot means (``time_to_goal``,
    ``path_length``, ``path_efficiency``) are floats, NaN where undefined.

    Raises:
        MimicsError: when ``folder`` is not a battery folder.
    """
    store = BatteryStore.open(folder)
    try:
        rows = store.rows()
    finally:
        store.close()
    table = pd.DataFrame(rows)
    if table.empty:
        return table
    for metric in ("success", *SUMMARY_STATS):
        table[metric] = [row_value(row, metric) for row in rows]
    for column in COUNTS:
        table[column] = table[column].astype("Int64")
    table["parameters"] = table["label"]
    params = [json.loads(p) for p in table["params"]]
    names = list(dict.fromkeys(k for p in params for k in p))
    for name in names:
        table[f"param_{name}"] = [p.get(name) for p in params]
    trouble = table[list(TROUBLE)].fillna(0).gt(0).any(axis=1)
    unfinished = table["state"].isin(("pending", "running"))
    table["misbehaving"] = ((table["state"] != "done") & ~unfinished) | trouble
    table["folder"] = [str(Path(folder) / RUNS_DIR / f) for f in table["folder"]]
    return table


def aggregate(table: pd.DataFrame) -> pd.DataFrame:
    """Per algorithm x scenario x parameter point: runs by outcome, means and 95% intervals.

    Means are over the ``done`` runs; ``X_ci95`` is the half-width of the 95%
    confidence interval of the mean of ``X`` (NaN with fewer than two runs).
    """
    groups = []
    for (algorithm, scenario, label), group in table.groupby(
            ["algorithm", "scenario", "parameters"], sort=False):
        done = group[group["state"] == "done"]
        row: dict[str, Any] = {
            "algorithm": algorithm, "scenario": scenario, "parameters": label,
            "runs": len(group), "done": len(done),
            "failed": int(group["state"].isin(FAILED_STATES).sum()),
            "unfinished": int(group["state"].isin(("pending", "running")).sum()),
            "misbehaving": int(group["misbehaving"].sum())}
        for metric in METRICS:
            values = done[metric].dropna().to_numpy(dtype=float)
            row[metric], row[f"{metric}_ci95"] = mean_ci95(values)
        groups.append(row)
    return pd.DataFrame(groups)


def mean_ci95(values: np.ndarray) -> tuple[float, float]:
    """The mean and the half-width of its 95% confidence interval (Student's t).

    >>> mean_ci95(np.array([1.0, 2.0, 3.0]))
    (2.0, 2.484...)
    """
    n = len(values)
    if n == 0:
        return math.nan, math.nan
    mean = float(values.mean())
    if n < 2:
        return mean, math.nan
    from scipy.stats import t

    return mean, float(t.ppf(0.975, n - 1) * values.std(ddof=1) / math.sqrt(n))


def export_table(table: pd.DataFrame, path: str | Path, fmt: str | None = None) -> Path:
    """Write the per-run table as CSV or Parquet.

    Args:
        table: from :func:`runs_table`.
        path: the file to write.
        fmt: ``"csv"`` or ``"parquet"`` (None: ``csv`` for a ``.csv`` file, else Parquet).
            The CSV leaves out tracebacks (multi-line); Parquet keeps them.

    Raises:
        MimicsError: when the file cannot be written.
    """
    out = Path(path)
    params = [c for c in table.columns if c.startswith("param_")]
    columns = [c for c in EXPORT_COLUMNS if c in table.columns]
    at = columns.index("parameters") + 1 if "parameters" in columns else len(columns)
    columns[at:at] = params
    try:
        if (fmt or ("csv" if out.suffix.lower() == ".csv" else "parquet")) == "csv":
            table[columns].to_csv(out, index=False)
        else:
            table[[*columns, "traceback"]].to_parquet(out, index=False)
    except (OSError, ValueError, ImportError) as exc:
        raise MimicsError(f"{out}: cannot write the table: {exc}") from None
    return out


# -- printing ------------------------------------------------------------------------

def print_report(table: pd.DataFrame, console: Console, *, only_misbehaving: bool = False,
                 runs: bool = True, baseline: str | None = None,
                 metrics: list[str] | None = None) -> None:
    """Print the per-run table, the failures, the intervals per cell, the paired
    comparison (with two or more algorithms) and the identical-seed warnings."""
    from mimics.batteries.comparison import (
        cell_intervals,
        identical_seed_warnings,
        paired_comparison,
        randomize_hints,
    )
    from mimics.batteries.tables import comparison_rich, intervals_rich

    if table.empty:
        console.print("the battery has no runs", markup=False)
        return
    shown = table[table["misbehaving"]] if only_misbehaving else table
    if runs:
        console.print(_runs_rich(shown))
    failures = table[table["state"].isin(FAILED_STATES)]
    if len(failures):
        console.print(f"\n{len(failures)} failed run(s):", style="bold red")
        for row in failures.itertuples():
            console.print(f"  #{row.id} {row.state}: {row.error}", markup=False,
                          highlight=False)
    console.print(intervals_rich(cell_intervals(table, metrics), metrics))
    if table["algorithm"].nunique() > 1:
        console.print(comparison_rich(paired_comparison(table, baseline, metrics)))
    for line in identical_seed_warnings(table, randomize_hints(table)):
        console.print(f"warning: {line}", style="yellow", markup=False, highlight=False)


def _cell(value: Any, digits: int = 0) -> str:
    if value is None or value is pd.NA or (isinstance(value, float) and math.isnan(value)):
        return "-"
    return f"{value:.{digits}f}" if digits else str(value)


def _runs_rich(table: pd.DataFrame) -> Table:
    rich = Table(title="Runs (! = misbehaved)", show_lines=False, header_style="bold")
    for name in ("", "#", "algorithm", "scenario", "parameters", "seed", "state", "reached",
                 "collisions", "deadlocks", "livelocks", "escaped", "exceptions", "wall (s)",
                 "sim (s)"):
        rich.add_column(name, justify="right" if name not in ("algorithm", "scenario",
                                                              "parameters", "state") else "left")
    for row in table.itertuples():
        style = ("red" if row.state in FAILED_STATES else
                 "yellow" if row.misbehaving else "dim" if row.state != "done" else None)
        rich.add_row("!" if row.misbehaving else "", str(row.id), row.algorithm, row.scenario,
                     row.parameters, str(row.seed), row.state, _cell(row.reached_goal),
                     _cell(row.collisions), _cell(row.deadlocks), _cell(row.livelocks),
                     _cell(row.escaped), _cell(row.exceptions), _cell(row.wall_time, 2),
                     _cell(row.sim_time, 1), style=style)
    return rich
