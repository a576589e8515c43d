"""Per-run metrics of a battery: what they are, how a run's value is read, its digest.

Each finished run has one value of each metric. A run that failed (error,
time-out, crash) counts as bringing no robot home (success 0, reached goal 0)
and has no value of the metrics that need a finished run; goal metrics are
undefined (NaN, shown as n/a) where no robot has a goal. Time to goal is the
restricted mean, defined for every finished run with a goal robot: robots that
never arrived count at the run's horizon. The values come from the run's
database row: the outcome counts and, for the metrics that a count cannot
give, the ``metrics`` JSON the worker took from the run's summary.json.

A run's digest fingerprints what it did: the summary's ``trajectory_digest``
(a hash of every recorded pose) with its outcome, or the outcome alone in runs
whose summary has no trajectory digest. Two seeds with the same digest gave
identical runs: their seed changed nothing.

>>> row_value({"state": "done", "robots": 4, "reached_goal": 4}, "success")
1.0
>>> row_value({"state": "error", "robots": 4, "reached_goal": None}, "reached_goal")
0.0
>>> row_value({"state": "error", "robots": 4, "reached_goal": None}, "collisions")
nan
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from mimics.batteries.states import FAILED_STATES


@dataclass(frozen=True)
class Metric:
    """A per-run metric.

    Attributes:
        name: its name in tables, ``--metric`` and ``[battery.until]``.
        description: what it measures, with its unit.
        proportion: a 0/1 value per run (Wilson intervals), not a mean (t intervals).
        needs_goal: it means nothing where no robot has a goal (shown as n/a there).
        conditional: the robots it is restricted to (``""``: every robot of the run); a
            comparison on it says it is conditional and on how many pairs.
        cost: what the run cost to compute, not what it did: never in the default
            comparison, shown in the report's cost table.
        if_failed: its value for a run that failed (error, time-out, crash); None: missing.
    """

    name: str
    description: str
    proportion: bool = False
    needs_goal: bool = False
    conditional: str = ""
    cost: bool = False
    if_failed: float | None = None


ARRIVED = "robots that arrived"
METRICS: dict[str, Metric] = {m.name: m for m in (
    Metric("success", "runs where every robot with a goal reached it (a proportion; a failed "
                      "run counts as 0)", proportion=True, needs_goal=True, if_failed=0.0),
    Metric("reached_goal", "robots that reached their goal (a failed run counts as 0)",
           needs_goal=True, if_failed=0.0),
    Metric("collisions", "collisions (robot-robot and robot-wall)"),
    Metric("deadlocks", "robots ever in a deadlock"),
    Metric("livelocks", "robots ever in a livelock"),
    Metric("escaped", "robots that left the map"),
    Metric("exceptions", "exceptions raised by user code"),
    Metric("time_to_goal", "restricted mean time to goal (s): each robot with a goal counted at "
                           "its arrival, one that never arrived at the run's horizon (its time "
                           "limit)", needs_goal=True),
    Metric("time_to_goal_arrived", "mean time to goal of the robots that arrived (s), "
                                   "conditional on arriving", needs_goal=True,
           conditional=ARRIVED),
    Metric("path_length", "mean path length of the robots (m); robots that stop early (stuck, "
                          "collided) travel less"),
    Metric("path_efficiency", "mean straight-line / travelled distance of the robots that "
                              "arrived, conditional on arriving", needs_goal=True,
           conditional=ARRIVED),
    Metric("sim_time", "simulated seconds until the run ended"),
    Metric("wall_time", "wall-clock seconds of the run (a cost, not deterministic)", cost=True),
    Metric("user_time", "seconds spent in the algorithm's code (a cost, not deterministic)",
           cost=True),
)}
#: Metrics stored per run in the database's ``metrics`` JSON (from summary.json).
SUMMARY_STATS = ("time_to_goal", "time_to_goal_arrived", "path_length", "path_efficiency",
                 "user_time")
#: What the ``metrics`` JSON also keeps of a run's arrivals (for arrival curves, n/a cells).
ARRIVAL_KEYS = ("goal_robots", "horizon", "arrival_times")
#: Metrics of the default comparison table: outcomes, never costs.
DEFAULT_COMPARED = ("success", "time_to_goal", "reached_goal", "collisions")
#: Cost metrics, in the report's cost table.
COSTS = tuple(name for name, metric in METRICS.items() if metric.cost)
#: Keys of the summary that make up a run's outcome in its digest.
_OUTCOME_KEYS = ("status", "steps", "sim_time", "robots", "reached_goal", "collisions",
                 "robot_collisions", "wall_collisions", "escaped", "deadlocks", "livelocks",
                 "exceptions", "active_at_end", "time_to_goal", "path_length",
                 "path_efficiency")


def check_metric(name: str, where: str) -> Metric:
    """The metric named ``name``.

    Raises:
        ValueError: one line naming ``where``, the name and the known metrics.
    """
    if name not in METRICS:
        raise ValueError(f"{where}: unknown metric {name!r} (expected one of: "
                         f"{', '.join(METRICS)})")
    return METRICS[name]


def summary_metrics(summary: Mapping[str, Any]) -> dict[str, Any]:
    """What a worker stores for a run, from its summary.json (None: undefined).

    The per-run metrics of :data:`SUMMARY_STATS` and, for runs whose summary has
    ``arrivals``, the goal robots, the horizon and the arrival times.
    """
    def mean_of(key: str) -> float | None:
        stats = summary.get(key)
        return _finite(stats.get("mean") if isinstance(stats, Mapping) else None)

    timing = summary.get("user_code_time")
    found: dict[str, Any] = {
        "time_to_goal": None, "time_to_goal_arrived": mean_of("time_to_goal"),
        "path_length": mean_of("path_length"), "path_efficiency": mean_of("path_efficiency"),
        "user_time": (_finite(timing.get("mean", 0.0) * timing.get("calls", 0))
                      if isinstance(timing, Mapping) and timing.get("calls") else None)}
    arrivals = summary.get("arrivals")
    if isinstance(arrivals, Mapping):
        found["time_to_goal"] = _finite(arrivals.get("restricted_mean"))
        found["goal_robots"] = int(arrivals.get("goal_robots") or 0)
        found["horizon"] = _finite(arrivals.get("horizon"))
        found["arrival_times"] = [float(t) for t in arrivals.get("times") or ()]
    return found


def _finite(value: Any) -> float | None:
    if value is None or isinstance(value, bool) or not isinstance(value, int | float):
        return None
    return float(value) if math.isfinite(value) else None


def run_digest(summary: Mapping[str, Any]) -> str:
    """The run's fingerprint: ``"t:HEX"`` with the summary's ``trajectory_digest``, else
    ``"o:HEX"`` from the outcome alone (times to the bit, counts, path statistics)."""
    outcome = {key: summary.get(key) for key in _OUTCOME_KEYS}
    trajectory = summary.get("trajectory_digest")
    kind = "t" if isinstance(trajectory, str) and trajectory else "o"
    text = json.dumps({"outcome": outcome, "trajectory": trajectory if kind == "t" else None},
                      sort_keys=True, default=repr)
    return f"{kind}:{hashlib.sha256(text.encode()).hexdigest()[:32]}"


def stored_metrics(row: Mapping[str, Any]) -> dict[str, Any]:
    """The ``metrics`` JSON of a database row, as a dict (empty without one).

    A battery run before time to goal became a restricted mean stored the mean
    over arrivals as ``time_to_goal``: it is read as ``time_to_goal_arrived``,
    and the restricted mean is undefined for it.
    """
    stored = row.get("metrics")
    values = json.loads(stored) if isinstance(stored, str) and stored else {}
    if "time_to_goal_arrived" not in values and "time_to_goal" in values:
        values = {**values, "time_to_goal_arrived": values["time_to_goal"],
                  "time_to_goal": None}
    return values


def row_value(row: Mapping[str, Any], metric: str, *, count_failed: bool = True) -> float:
    """A run's value of ``metric`` from its database row (NaN: undefined or unfinished).

    A failed run (error, time-out, crash) has the metric's ``if_failed`` value
    (success and reached goal 0: a run that failed brought no robot home), unless
    ``count_failed`` is False; metrics that need a finished run are NaN for it.
    Goal metrics are NaN for a run with no robot that has a goal.
    """
    state = row.get("state")
    if state in FAILED_STATES:
        value = METRICS[metric].if_failed
        return math.nan if value is None or not count_failed else value
    if state != "done":
        return math.nan
    values = stored_metrics(row)
    if METRICS[metric].needs_goal and values.get("goal_robots") == 0:
        return math.nan
    if metric == "success":
        robots, reached = values.get("goal_robots", row.get("robots")), row.get("reached_goal")
        if is_missing(robots) or is_missing(reached):
            return math.nan
        return float(int(reached) >= int(robots))
    if metric in SUMMARY_STATS:
        value = values.get(metric)
        return math.nan if value is None else float(value)
    value = row.get(metric)
    return math.nan if is_missing(value) else float(value)


def is_missing(value: Any) -> bool:
    """None, NaN or pandas.NA: no value."""
    if value is None:
        return True
    try:
        return bool(math.isnan(value))
    except TypeError:  # pandas.NA
        return True
