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

from mimics.batteries.metrics import METRICS as METRIC_TABLE
from mimics.batteries.metrics import SUMMARY_STATS, row_value, stored_metrics
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
                  "status", *COUNTS, "success", *SUMMARY_STATS, "goal_robots", "horizon",
                  "sim_time", "wall_time",
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
    stored = [stored_metrics(row) if row.get("state") == "done" else {} for row in rows]
    table["goal_robots"] = pd.array([s.get("goal_robots") for s in stored], dtype="Int64")
    table["horizon"] = [float(s.get("horizon") or math.nan) for s in stored]
    table["arrival_times"] = [s.get("arrival_times") for s in stored]
    for column in COUNTS:
        table[column] = table[column].astype("Int64")
    table["parameters"] = table["label"]
    _no_goal_cells(table)
    params = [json.loads(p) for p in table["params"]]
    names = list(dict.fromkeys(k for p in params for k in p))
    for name in names:
        table[f"param_{name}"] = [p.get(name) for p in params]
    trouble = table[list(TROUBLE)].fillna(0).gt(0).any(axis=1)
    unfinished = table["state"].isin(("pending", "running"))
    table["misbehaving"] = ((table["state"] != "done") & ~unfinished) | trouble
    table["folder"] = [str(Path(folder) / RUNS_DIR / f) for f in table["folder"]]
    return table


def _no_goal_cells(table: pd.DataFrame) -> None:
    """Mark (``goal_less``) the runs of cells whose finished runs have no robot with a goal,
    and make their goal metrics n/a (NaN): a failed run there brought no robot home
    because none had a home to go to."""
    needs_goal = [name for name, metric in METRIC_TABLE.items()
                  if metric.needs_goal and name in table.columns]
    table["goal_less"] = False
    for _, group in table.groupby(["algorithm", "scenario", "label"], sort=False):
        known = group["goal_robots"].dropna()
        if len(known) and (known == 0).all():
            table.loc[group.index, needs_goal] = math.nan
            table.loc[group.index, "goal_less"] = True


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
