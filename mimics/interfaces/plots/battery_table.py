"""A battery folder's runs as one table (summaries, and the battery's own states)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from mimics.batteries.tasks import STATE_OF_STATUS
from mimics.world.errors import MimicsError

_NUMERIC = ("robots", "wall_time", "sim_time", "reached_goal", "collisions", "escaped",
            "deadlocks", "livelocks", "exceptions", "active_at_end", "collided_at_end")


def battery_table(directory: str | Path) -> pd.DataFrame:
    """One row per run of a battery folder.

    Outcomes come from each run folder's ``summary.json``. When the folder has
    a ``battery.db``, the battery's own report (``mimics.batteries.report``)
    adds the runs that left no summary (crashed, timed out, pending) and gives
    every run its battery names; a finished run's status is then the engine's
    (completed, time_limit...) and a failed one's the battery state (error,
    timeout, crashed).

    Columns: folder, scenario, algorithm, seed, status, state (the battery's:
    done, error, timeout, crashed...), parameters (a JSON string), point (the
    parameter point's label, ``"robots=10"``: the battery's own, or else the
    parameters that differ between the runs of a scenario), the counts of
    :data:`OUTCOMES`, robots, wall_time, sim_time, and the run's arrivals:
    time_to_goal (the restricted mean: each goal robot's arrival time, a robot
    that never arrived counted at the horizon), time_to_goal_arrived (the mean
    over the robots that arrived), horizon, goal_robots, arrived and
    arrival_times (a list; None for runs without an outcome and runs recorded
    before mimics kept arrivals, whose other arrival columns are NaN).

    Raises:
        MimicsError: when the folder does not exist or holds no run.
    """
    root = Path(directory)
    if not root.is_dir():
        raise MimicsError(f"{root}: not a battery folder (no such directory)")
    summaries: dict[Path, dict[str, Any]] = {}
    for path in sorted(root.rglob("summary.json")):
        row = _summary_row(path)
        if row is not None:
            summaries[path.parent.resolve()] = row
    rows = _with_battery_states(root, summaries)
    if not rows:
        raise MimicsError(f"{root}: no run summaries (summary.json) found: not a battery folder "
                          "or no run has finished")
    table = pd.DataFrame(rows)
    table["point"] = _points(table)
    # runs recorded before collided_at_end: collisions deactivated, so they are the same
    table["collided_at_end"] = table["collided_at_end"].fillna(table["collisions"])
    stopped = (table["robots"] - table["reached_goal"] - table["collided_at_end"]
               - table["escaped"] - table["active_at_end"])
    table["stopped_other"] = stopped.clip(lower=0)
    return table


def _summary_row(path: Path) -> dict[str, Any] | None:
    """A table row from one summary.json (None when unreadable: being written or broken)."""
    try:
        summary = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    if not isinstance(summary, dict) or "scenario" not in summary:
        return None
    row = {"folder": str(path.parent), "scenario": str(summary["scenario"]),
           "algorithm": str(summary.get("algorithm", "?")), "seed": summary.get("seed"),
           "status": str(summary.get("status", "?")),
           "parameters": json.dumps(summary.get("parameters") or {}, sort_keys=True,
                                    default=str),
           "state": STATE_OF_STATUS.get(str(summary.get("status")), "error"),
           **_arrival_columns(summary)}
    for key in _NUMERIC:
        value = summary.get(key)
        row[key] = float(value) if isinstance(value, int | float) else math.nan
    return row


def _with_battery_states(root: Path, summaries: dict[Path, dict[str, Any]]
                         ) -> list[dict[str, Any]]:
    """Rows for every run the battery's database knows, else the summaries alone."""
    if not (root / "battery.db").is_file():
        return list(summaries.values())
    try:
        from mimics.batteries.report import runs_table

        runs = runs_table(root)
    except (ImportError, MimicsError):
        return list(summaries.values())
    if runs.empty:
        return list(summaries.values())
    rows: list[dict[str, Any]] = []
    for run in runs.to_dict("records"):
        folder = Path(str(run["folder"])).resolve()
        row = dict(summaries.get(folder) or {
            "folder": str(folder), "status": str(run["state"]), **_arrival_columns({}),
            "parameters": json.dumps(json.loads(run.get("params") or "{}"), sort_keys=True),
            **dict.fromkeys(_NUMERIC, math.nan)})
        row.update(algorithm=str(run["algorithm"]), scenario=str(run["scenario"]),
                   seed=run["seed"], state=str(run["state"]))
        if isinstance(run.get("parameters"), str):  # the battery's own label of the point
            row["point"] = run["parameters"]
        if "arrival_times" in run:  # the database's record, when it keeps one
            row.update(_arrivals_of_run(run))
        if run["state"] != "done":
            row["status"] = str(run["state"])
        rows.append(row)
    return rows


def _arrival_columns(summary: dict[str, Any]) -> dict[str, Any]:
    """A summary's arrivals (NaN and None for a run recorded without them)."""
    arrivals = summary.get("arrivals")
    arrivals = arrivals if isinstance(arrivals, dict) else {}
    times = arrivals.get("times")
    return {"time_to_goal": _float(arrivals.get("restricted_mean")),
            "time_to_goal_arrived": _float((summary.get("time_to_goal") or {}).get("mean")),
            "horizon": _float(arrivals.get("horizon")),
            "goal_robots": _float(arrivals.get("goal_robots")),
            "arrived": _float(arrivals.get("arrived")),
            "arrival_times": [float(t) for t in times] if isinstance(times, list) else None}


def _arrivals_of_run(run: dict[str, Any]) -> dict[str, Any]:
    """The arrival columns of a row of the battery's runs table."""
    times = run.get("arrival_times")
    times = None if times is None or isinstance(times, float) else [float(t) for t in times]
    return {"time_to_goal": _float(run.get("time_to_goal")),
            "time_to_goal_arrived": _float(run.get("time_to_goal_arrived")),
            "horizon": _float(run.get("horizon")), "goal_robots": _float(run.get("goal_robots")),
            "arrived": math.nan if times is None else float(len(times)),
            "arrival_times": times}


def _float(value: Any) -> float:
    """A number, or NaN for None, pandas' NA and anything not a number."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        return math.nan
    return float(value)


def _points(table: pd.DataFrame) -> list[str]:
    """Each run's parameter point: the battery's label where the database gave one, else
    the parameters that differ between the runs of its scenario (``"robots=10"``)."""
    given = table["point"] if "point" in table.columns else pd.Series([None] * len(table))
    params = [json.loads(p) if p else {} for p in table["parameters"]]
    varying: dict[str, list[str]] = {}
    for scenario in set(table["scenario"]):
        mine = [p for p, s in zip(params, table["scenario"], strict=True) if s == scenario]
        keys = sorted({k for p in mine for k in p} - {"seed"})
        varying[scenario] = [k for k in keys
                             if len({json.dumps(p.get(k), sort_keys=True) for p in mine}) > 1]
    return [point if isinstance(point, str) else
            ", ".join(f"{k}={p.get(k)}" for k in varying[scenario])
            for point, p, scenario in zip(given, params, table["scenario"], strict=True)]
