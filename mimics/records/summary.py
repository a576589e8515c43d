"""summary.json and summary.txt: the outcome of one run, for a program and for a person.

summary.json holds every key of :meth:`mimics.engine.outcome.RunResult.summary`
(status, times, counts with robot-robot and robot-wall collisions apart,
deadlocks and livelocks as robots ever in one, user-code timing, time to goal,
path length and efficiency) plus what the recorder adds: the run's uuid and
creation time, mimics version, policy and limits, stall episodes, message
counts and a ``records`` table: rows and steps written, ``every``, whether
robot logs were written, and the wall time spent recording, in the step loop
(``step_time``) and at the end (``write_time``: merging, logs, summaries).
It is written last, so its presence means the run finished and was recorded.

>>> rows = summary_rows({"scenario": "line", "algorithm": "go_to_goal", "seed": 1,
...                      "status": "completed", "robots": 2, "reached_goal": 2})
>>> rows[0], rows[1]
(('status', 'completed'), ('robots', '2'))
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from mimics.engine.outcome import RunResult
from mimics.records.layout import SUMMARY_JSON, SUMMARY_TXT


def write_json_atomic(path: Path, data: Any) -> None:
    """Write JSON through a temporary file and a rename, so readers never see half a file."""
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(data, indent=2, default=_jsonable) + "\n")
    os.replace(tmp, path)


def _jsonable(value: Any) -> Any:
    if hasattr(value, "item"):
        return value.item()
    if hasattr(value, "tolist"):
        return value.tolist()
    return str(value)


def write_summary(result: RunResult, folder: Path, extra: dict[str, Any] | None = None) -> Path:
    """Write summary.txt, then summary.json (last), for ``result`` into ``folder``.

    Args:
        result: the run's outcome.
        folder: the run folder (created if needed).
        extra: keys added to (or replacing) those of ``result.summary()``.

    Returns:
        The path of summary.json.
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    summary = {**result.summary(), **(extra or {})}
    (folder / SUMMARY_TXT).write_text(summary_text(summary))
    path = folder / SUMMARY_JSON
    write_json_atomic(path, summary)
    return path


def _seconds(value: float | None) -> str:
    """A duration with a unit that suits it."""
    if value is None:
        return "-"
    if value < 1e-3:
        return f"{value * 1e6:.3g} us"
    if value < 1:
        return f"{value * 1e3:.3g} ms"
    return f"{value:.4g} s"


def _stats(stats: dict[str, Any] | None, unit: str, digits: int = 4) -> str:
    if not stats or stats.get("mean") is None:
        return "-"
    unit = f" {unit}" if unit else ""
    return (f"mean {stats['mean']:.{digits}g}{unit}, min {stats['min']:.{digits}g}, "
            f"max {stats['max']:.{digits}g}")


def _restricted(arrivals: dict[str, Any]) -> str:
    """The restricted mean time to goal, its horizon and how many arrived."""
    return (f"{arrivals['restricted_mean']:.4g} s restricted mean, each robot that never "
            f"arrived counted at the {arrivals['horizon']:g} s horizon "
            f"({arrivals['arrived']} of {arrivals['goal_robots']} arrived)")


def summary_rows(summary: dict[str, Any]) -> list[tuple[str, str]]:
    """``(label, value)`` rows of a summary, the same for summary.txt and ``mimics report``.

    Keys missing from ``summary`` (an older or partial summary) are left out.
    """
    s = summary
    rows: list[tuple[str, str]] = []

    def add(label: str, *keys: str, text: str | None = None) -> None:
        if all(k in s for k in keys):
            rows.append((label, text if text is not None else str(s[keys[0]])))

    add("status", "status")
    add("robots", "robots")
    add("reached goal", "reached_goal")
    add("collisions", "collisions", "robot_collisions", "wall_collisions",
        text=f"{s.get('collisions')} (robot-robot {s.get('robot_collisions')}, "
             f"robot-wall {s.get('wall_collisions')})")
    add("escaped", "escaped")
    add("deadlocks", "deadlocks", text=f"{s.get('deadlocks')} robots"
        + (f", {s['deadlock_episodes']} episodes" if "deadlock_episodes" in s else ""))
    add("livelocks", "livelocks", text=f"{s.get('livelocks')} robots"
        + (f", {s['livelock_episodes']} episodes" if "livelock_episodes" in s else ""))
    add("exceptions", "exceptions")
    add("active at end", "active_at_end")
    if "sim_time" in s:
        steps = f" ({s['steps']} steps)" if "steps" in s else ""
        rows.append(("simulated time", f"{s['sim_time']:.6g} s{steps}"))
    if "wall_time" in s:
        speed = s.get("sim_speed")
        paced = s.get("paced_wall_time")  # a live run: its pacing and pauses apart
        rows.append(("wall time", f"{s['wall_time']:.3f} s"
                     + (f" ({speed:.3g} s_sim/s)" if speed else "")
                     + (" in the engine" if paced is not None else "")))
        if paced is not None:
            rows.append(("paced wall time", f"{paced:.3f} s from start to end, pacing and "
                                            "pauses included"))
    timing = s.get("user_code_time")
    if timing and timing.get("calls"):
        rows.append(("user code per call", f"mean {_seconds(timing['mean'])}, p95 "
                     f"{_seconds(timing['p95'])}, max {_seconds(timing['max'])} "
                     f"({timing['calls']} calls)"))
    arrivals = s.get("arrivals")
    if isinstance(arrivals, dict) and arrivals.get("restricted_mean") is not None:
        rows.append(("time to goal", _restricted(arrivals)))
        if arrivals.get("arrived"):
            add("  of those that arrived", "time_to_goal",
                text=_stats(s.get("time_to_goal"), "s") + f" (n = {arrivals['arrived']})")
    else:
        add("time to goal", "time_to_goal", text=_stats(s.get("time_to_goal"), "s"))
    add("path length", "path_length", text=_stats(s.get("path_length"), "m"))
    efficiency = _stats(s.get("path_efficiency"), "")
    add("path efficiency", "path_efficiency",
        text=efficiency + (" (of those that arrived)" if efficiency != "-" else ""))
    add("user messages", "user_messages")
    records = s.get("records")
    if isinstance(records, dict) and "trajectory_rows" in records:
        rows.append(("recording", f"{records['trajectory_rows']} trajectory rows, "
                     f"{records.get('step_time', 0.0):.3g} s during the run + "
                     f"{records.get('write_time', 0.0):.3g} s at its end"))
    add("error", "error")
    if rows and rows[-1] == ("error", ""):
        rows.pop()
    add("policy", "policy")
    add("created", "created")
    add("run uuid", "run_uuid")
    add("mimics version", "mimics_version")
    return rows


def summary_text(summary: dict[str, Any]) -> str:
    """summary.txt: a title line and one aligned ``label  value`` line per row."""
    title = (f"{summary.get('scenario', '?')} / {summary.get('algorithm', '?')} / seed "
             f"{summary.get('seed', '?')}")
    rows = summary_rows(summary)
    width = max((len(label) for label, _ in rows), default=0)
    indent = "\n" + " " * (width + 2)  # a value's later lines (an error's source line) align
    lines = [title, "=" * len(title),
             *(f"{label:<{width}}  {str(value).replace(chr(10), indent)}" for label, value in rows)]
    return "\n".join(lines) + "\n"
