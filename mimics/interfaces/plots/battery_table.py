"""A battery folder's runs as one table (summaries, and the battery's own states)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import pandas as pd

from mimics.world.errors import MimicsError

_NUMERIC = ("robots", "wall_time", "sim_time", "reached_goal", "collisions", "escaped",
            "deadlocks", "livelocks", "exceptions", "active_at_end")


def battery_table(directory: str | Path) -> pd.DataFrame:
    """One row per run of a battery folder.

    Outcomes come from each run folder's ``summary.json``. When the folder has
    a ``battery.db``, the battery's own report (``mimics.batteries.report``)
    adds the runs that left no summary (crashed, timed out, pending) and gives
    every run its battery names; a finished run's status is then the engine's
    (completed, time_limit...) and a failed one's the battery state (error,
    timeout, crashed).

    Columns: folder, scenario, algorithm, seed, status, parameters (a JSON
    string), the counts of :data:`OUTCOMES`, robots, wall_time, sim_time and
    time_to_goal_mean (NaN for runs without an outcome).

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
    stopped = (table["robots"] - table["reached_goal"] - table["collisions"]
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
           "time_to_goal_mean": (summary.get("time_to_goal") or {}).get("mean")}
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
            "folder": str(folder), "status": str(run["state"]), "time_to_goal_mean": None,
            "parameters": json.dumps(json.loads(run.get("params") or "{}"), sort_keys=True),
            **dict.fromkeys(_NUMERIC, math.nan)})
        row.update(algorithm=str(run["algorithm"]), scenario=str(run["scenario"]),
                   seed=run["seed"])
        if run["state"] != "done":
            row["status"] = str(run["state"])
        rows.append(row)
    return rows
