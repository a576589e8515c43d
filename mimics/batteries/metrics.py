"""Per-run metrics of a battery: what they are, how a run's value is read, its digest.

Each finished run has one value of each metric (NaN when undefined: a run that
failed, or a time to goal when no robot reached its goal). The values come from
the run's database row: the outcome counts and, for the metrics that a count
cannot give, the ``metrics`` JSON the worker took from the run's summary.json.

A run's digest fingerprints what it did: the summary's ``trajectory_digest``
(a hash of every recorded pose) with its outcome, or the outcome alone in runs
whose summary has no trajectory digest. Two seeds with the same digest gave
identical runs: their seed changed nothing.

>>> row_value({"state": "done", "robots": 4, "reached_goal": 4}, "success")
1.0
>>> row_value({"state": "error", "robots": 4, "reached_goal": None}, "reached_goal")
nan
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Metric:
    """A per-run metric.

    Attributes:
        name: its name in tables, ``--metric`` and ``[battery.until]``.
        description: what it measures, with its unit.
        proportion: a 0/1 value per run (Wilson intervals), not a mean (t intervals).
    """

    name: str
    description: str
    proportion: bool = False


METRICS: dict[str, Metric] = {m.name: m for m in (
    Metric("success", "runs where every robot reached its goal (a proportion)", True),
    Metric("reached_goal", "robots that reached their goal"),
    Metric("collisions", "collisions (robot-robot and robot-wall)"),
    Metric("deadlocks", "robots ever in a deadlock"),
    Metric("livelocks", "robots ever in a livelock"),
    Metric("escaped", "robots that left the map"),
    Metric("exceptions", "exceptions raised by user code"),
    Metric("time_to_goal", "mean time to goal of the robots that reached it (s)"),
    Metric("path_length", "mean path length of the robots (m)"),
    Metric("path_efficiency", "mean straight-line / travelled distance of the robots that "
                              "reached their goal"),
    Metric("sim_time", "simulated seconds until the run ended"),
    Metric("wall_time", "wall-clock seconds of the run"),
)}
#: Metrics read from the summary's per-robot statistics (their mean over robots).
SUMMARY_STATS = ("time_to_goal", "path_length", "path_efficiency")
#: Metrics of the default comparison table.
DEFAULT_COMPARED = ("success", "reached_goal", "collisions", "time_to_goal", "path_efficiency",
                    "wall_time")
#: Keys of the summary that make up a run's outcome in its digest.
_OUTCOME_KEYS = ("status", "steps", "sim_time", "robots", "reached_goal", "collisions",
                 "robot_collisions", "wall_collisions", "escaped", "deadlocks", "livelocks",
                 "exceptions", "active_at_end", *SUMMARY_STATS)


def check_metric(name: str, where: str) -> Metric:
    """The metric named ``name``.

    Raises:
        ValueError: one line naming ``where``, the name and the known metrics.
    """
    if name not in METRICS:
        raise ValueError(f"{where}: unknown metric {name!r} (expected one of: "
                         f"{', '.join(METRICS)})")
    return METRICS[name]


def summary_metrics(summary: Mapping[str, Any]) -> dict[str, float | None]:
    """The metrics a worker stores for a run, from its summary.json (None: undefined)."""
    found: dict[str, float | None] = {}
    for name in SUMMARY_STATS:
        stats = summary.get(name)
        value = stats.get("mean") if isinstance(stats, Mapping) else None
        found[name] = None if value is None or not math.isfinite(value) else float(value)
    return found


def run_digest(summary: Mapping[str, Any]) -> str:
    """The run's fingerprint: ``"t:HEX"`` with the summary's ``trajectory_digest``, else
    ``"o:HEX"`` from the outcome alone (times to the bit, counts, path statistics)."""
    outcome = {key: summary.get(key) for key in _OUTCOME_KEYS}
    trajectory = summary.get("trajectory_digest")
    kind = "t" if isinstance(trajectory, str) and trajectory else "o"
    text = json.dumps({"outcome": outcome, "trajectory": trajectory if kind == "t" else None},
                      sort_keys=True, default=repr)
    return f"{kind}:{hashlib.sha256(text.encode()).hexdigest()[:32]}"


def row_value(row: Mapping[str, Any], metric: str) -> float:
    """A run's value of ``metric`` from its database row (NaN: undefined or not done)."""
    if row.get("state") != "done":
        return math.nan
    if metric == "success":
        robots, reached = row.get("robots"), row.get("reached_goal")
        if _missing(robots) or _missing(reached):
            return math.nan
        return float(int(reached) >= int(robots))
    if metric in SUMMARY_STATS:
        stored = row.get("metrics")
        values = json.loads(stored) if isinstance(stored, str) and stored else {}
        value = values.get(metric)
        return math.nan if value is None else float(value)
    value = row.get(metric)
    return math.nan if _missing(value) else float(value)


def _missing(value: Any) -> bool:
    if value is None:
        return True
    try:
        return bool(math.isnan(value))
    except TypeError:  # pandas.NA
        return True
