"""Static plots: one run's trajectories, and a battery's outcomes and timings.

``plot_run`` draws every robot's path over the map, coloured by its final state,
with a mark where each robot was deactivated (or stood at the end) and a star
where a livelock was detected. ``battery_plots`` writes three figures for a
battery folder: robot outcomes and run statuses per algorithm x scenario,
time-to-goal distributions, and the paper's Figure 2 (wall time against number
of robots, from the runs of the ``line`` scenario).

>>> from mimics.interfaces.plots import FINAL_MARKS
>>> FINAL_MARKS[1]
('o', 'reached goal')
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from mimics.engine.state import Status
from mimics.interfaces.render import GOAL_COLOR, STATUS_COLORS, WALL_COLOR, status_color_table
from mimics.interfaces.replay import open_run, replay_data
from mimics.world.errors import MimicsError

#: Marker and legend label of each final state in a run plot.
FINAL_MARKS: dict[int, tuple[str, str]] = {
    Status.REACHED_GOAL: ("o", "reached goal"),
    Status.COLLIDED: ("X", "collided"),
    Status.ESCAPED: ("^", "escaped"),
    Status.DEADLOCK: ("s", "deadlock"),
    Status.ERROR: ("D", "error"),
    Status.REMOVED: ("+", "removed"),
    Status.ACTIVE: (".", "active at end"),
}
#: Robot outcomes stacked in the battery outcome plot: (summary column, label, colour).
OUTCOMES = (("reached_goal", "reached goal", STATUS_COLORS["reached_goal"]),
            ("collisions", "collided", STATUS_COLORS["collided"]),
            ("escaped", "escaped", STATUS_COLORS["escaped"]),
            ("stopped_other", "deadlock or error", STATUS_COLORS["deadlock"]),
            ("active_at_end", "active at end", STATUS_COLORS["active"]))
RUN_STATUS_COLORS = {"completed": "#2ca02c", "time_limit": "#1f77b4", "wall_limit": "#ff7f0e",
                     "stopped": "#8c8c8c", "error": "#d62728", "timeout": "#9467bd",
                     "crashed": "#000000", "pending": "#dddddd", "running": "#bcbd22"}
_NUMERIC = ("robots", "wall_time", "sim_time", "reached_goal", "collisions", "escaped",
            "deadlocks", "livelocks", "exceptions", "active_at_end")


def _new_figure(width_px: int, height_px: int, dpi: float = 100.0) -> Figure:
    if width_px < 100 or height_px < 100:
        raise MimicsError(f"plot size must be at least 100x100 pixels, got {width_px}x{height_px}")
    fig = Figure(figsize=(width_px / dpi, height_px / dpi), dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _save(fig: Figure, out: str | Path | None) -> Any:
    """Save a PNG at the figure's exact pixel size; one clear error if it cannot be written.

    ``out`` None: the figure itself is returned (for a notebook), not saved.
    """
    if out is None:
        return fig
    out = Path(out)
    try:
        out.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(out, dpi=fig.dpi, format="png")
    except OSError as exc:
        raise MimicsError(f"cannot write {out}: {exc.strerror or exc}") from None
    return out


# -- one run -------------------------------------------------------------------

def plot_run(run: str | Path | Any, out: str | Path | None, *, width_px: int = 1000,
             height_px: int = 800) -> Path | Figure:
    """Trajectories over the map with deactivation marks and a legend, as a PNG.

    Args:
        run: a run folder or a loaded run.
        out: the PNG to write (None: return the Matplotlib Figure instead).
        width_px: image width in pixels.
        height_px: image height in pixels.

    Returns:
        The path written (the Figure when ``out`` is None).

    Raises:
        MimicsError: not a run, an unreadable trajectory, or an unwritable ``out``.

    Example:
        >>> plot_run("runs/line-go_to_goal-s1", "run.png")  # doctest: +SKIP
    """
    loaded = open_run(run)
    data = replay_data(loaded)
    fig = _new_figure(width_px, height_px)
    ax = fig.add_subplot()
    scenario = data.scenario
    m = scenario.map
    ax.add_collection(LineCollection(m.segments.reshape(-1, 2, 2), colors=WALL_COLOR,
                                     linewidths=1.5, zorder=2))
    xmin, ymin, xmax, ymax = m.bounds
    ax.plot([xmin, xmax, xmax, xmin, xmin], [ymin, ymin, ymax, ymax, ymin], color="#cccccc",
            lw=0.8, ls="--", zorder=1)
    table = status_color_table()
    final = data.status[-1].astype(np.intp)
    paths = data.pose[:, :, :2].transpose(1, 0, 2)
    ax.add_collection(LineCollection(paths, colors=table[final], linewidths=0.9, alpha=0.6,
                                     zorder=3))
    start = scenario.stages
    ax.plot(start[:, 0], start[:, 1], ls="none", marker="o", ms=3, mfc="none", mec="#555555",
            mew=0.6, zorder=4)
    handles: list[Any] = [
        Line2D([], [], ls="none", marker="o", ms=5, mfc="none", mec="#555555", label="start")]
    goals = scenario.goals
    if np.isfinite(goals).any():
        ax.plot(goals[:, 0], goals[:, 1], ls="none", marker="x", ms=4, color=GOAL_COLOR,
                zorder=4)
        handles.append(Line2D([], [], ls="none", marker="x", ms=5, color=GOAL_COLOR,
                              label="goal"))
    end = data.pose[-1]
    for code, (marker, label) in FINAL_MARKS.items():
        chosen = final == code
        if not chosen.any():
            continue
        colour = table[code]
        ax.plot(end[chosen, 0], end[chosen, 1], ls="none", marker=marker, ms=7, color=colour,
                mec="black" if marker != "." else colour, mew=0.5, zorder=5)
        handles.append(Line2D([], [], ls="none", marker=marker, ms=7, color=colour,
                              mec="black" if marker != "." else colour, mew=0.5,
                              label=f"{label} ({int(chosen.sum())})"))
    stars = _livelock_points(data)
    if len(stars):
        ax.plot(stars[:, 0], stars[:, 1], ls="none", marker="*", ms=10,
                color=STATUS_COLORS["livelock"], mec="black", mew=0.4, zorder=6)
        handles.append(Line2D([], [], ls="none", marker="*", ms=10,
                              color=STATUS_COLORS["livelock"], mec="black", mew=0.4,
                              label=f"livelock detected ({len(stars)})"))
    pad_x, pad_y = 0.02 * (xmax - xmin), 0.02 * (ymax - ymin)
    ax.set_xlim(xmin - pad_x, xmax + pad_x)
    ax.set_ylim(ymin - pad_y, ymax + pad_y)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    summary = getattr(loaded, "summary", {}) or {}
    status = summary.get("status", "")
    ax.set_title(f"{data.title}: {status}, {data.duration:g} s simulated, {data.n} robots"
                 if status else data.title, fontsize=10)
    fig.legend(handles=handles, loc="outside right upper", fontsize=8, frameon=False)
    return _save(fig, out)


def _livelock_points(data: Any) -> np.ndarray:
    """Positions where a livelock started (rising edges of the livelock mask)."""
    mask = data.livelock
    rising = mask & ~np.vstack([np.zeros((1, mask.shape[1]), dtype=bool), mask[:-1]])
    k, r = np.nonzero(rising)
    return data.pose[k, r, :2].astype(np.float64)


# -- batteries -----------------------------------------------------------------

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


def _combo_labels(table: pd.DataFrame) -> list[tuple[str, str]]:
    return sorted({(a, s) for a, s in zip(table["algorithm"], table["scenario"], strict=True)})


def plot_outcomes(table: pd.DataFrame, out: str | Path | None, *, width_px: int = 1200,
                  height_px: int = 600) -> Path | Figure:
    """Robot outcomes (fractions of all robots) and run statuses per algorithm x scenario
    (``out`` None: the Figure is returned, not saved)."""
    combos = _combo_labels(table)
    fig = _new_figure(width_px, height_px)
    left, right = fig.subplots(1, 2, width_ratios=[3, 2])
    x = np.arange(len(combos))
    labels = [f"{a}\n{s}" for a, s in combos]
    bottom = np.zeros(len(combos))
    groups = table.groupby(["algorithm", "scenario"])
    for column, label, colour in OUTCOMES:
        totals = groups[column].sum()
        robots = groups["robots"].sum()
        frac = np.array([totals.get(c, 0.0) / max(robots.get(c, 0.0), 1.0) for c in combos])
        left.bar(x, frac, bottom=bottom, color=colour, label=label, width=0.7)
        bottom += frac
    runs = groups.size()
    without = groups["robots"].apply(lambda r: int(r.isna().sum()))
    for xi, combo in zip(x, combos, strict=True):
        text = f"{int(runs.get(combo, 0))} runs"
        if without.get(combo, 0):
            text += f", {int(without[combo])} without outcome"
        left.annotate(text, (xi, 1.0), ha="center", va="bottom", fontsize=7, xytext=(0, 2),
                      textcoords="offset points")
    left.set_xticks(x, labels, fontsize=8)
    left.set_ylim(0, 1.1)
    left.set_ylabel("fraction of robots")
    left.set_title("Robot outcomes", fontsize=10)
    left.legend(fontsize=7, loc="upper left", bbox_to_anchor=(0, -0.12), ncol=3, frameon=False)
    statuses = sorted(table["status"].unique(), key=lambda s: (s != "completed", s))
    counts = table.groupby(["algorithm", "scenario", "status"]).size()
    bottom = np.zeros(len(combos))
    for status in statuses:
        values = np.array([counts.get((*c, status), 0) for c in combos], dtype=float)
        right.bar(x, values, bottom=bottom, label=status, width=0.7,
                  color=RUN_STATUS_COLORS.get(status, "#bcbd22"))
        bottom += values
    right.set_xticks(x, labels, fontsize=8)
    right.set_ylabel("runs")
    right.set_title("Run statuses", fontsize=10)
    right.legend(fontsize=7, frameon=False)
    return _save(fig, out)


def plot_time_to_goal(table: pd.DataFrame, out: str | Path | None, *, width_px: int = 1000,
                      height_px: int = 600) -> Path | Figure:
    """Distributions of the time robots took to reach their goals, per algorithm x scenario.

    Per-robot times come from each run's ``reached_goal`` events; a run whose
    events cannot be read contributes its mean time to goal instead.
    """
    combos = _combo_labels(table)
    samples: list[np.ndarray] = []
    fallbacks = 0
    for combo in combos:
        chosen = table[(table["algorithm"] == combo[0]) & (table["scenario"] == combo[1])]
        values = []
        chosen = chosen[np.isfinite(chosen["robots"])]  # runs with an outcome
        for folder, mean in zip(chosen["folder"], chosen["time_to_goal_mean"], strict=True):
            times, per_robot = _goal_times(folder, mean)
            values.append(times)
            fallbacks += not per_robot
        samples.append(np.concatenate(values) if values else np.zeros(0))
    fig = _new_figure(width_px, height_px)
    ax = fig.add_subplot()
    shown = [s if s.size else np.array([np.nan]) for s in samples]
    ax.boxplot(shown, tick_labels=[f"{a}\n{s}" for a, s in combos], showfliers=True,
               flierprops={"markersize": 2})
    for k, s in enumerate(samples, start=1):
        ax.annotate(f"n={s.size}", (k, 1.0), xycoords=("data", "axes fraction"), ha="center",
                    va="bottom", fontsize=7)
    ax.set_ylabel("time to goal (s)")
    note = f" ({fallbacks} run(s) without readable events: their mean)" if fallbacks else ""
    ax.set_title(f"Time to goal per robot{note}", fontsize=10, pad=14)
    return _save(fig, out)


def _goal_times(folder: str, mean: Any) -> tuple[np.ndarray, bool]:
    """Per-robot goal times of one run from its events (True), or its mean (False)."""
    try:
        events = open_run(Path(folder)).events
        return events.loc[events["kind"] == "reached_goal", "time"].to_numpy(np.float64), True
    except Exception:  # an unreadable run falls back to its summary
        if isinstance(mean, int | float) and math.isfinite(mean):
            return np.array([float(mean)]), False
        return np.zeros(0), False


def plot_wall_time_vs_robots(table: pd.DataFrame, out: str | Path | None, *, scenario: str = "line",
                             width_px: int = 900, height_px: int = 600) -> Path | Figure:
    """The paper's Figure 2: mean wall time of a run against its number of robots.

    One line per algorithm and setting (the run parameters other than ``robots``
    that differ between runs),
    with the standard deviation over seeds as error bars and the slope of a
    linear fit (milliseconds per robot) in the legend.

    Raises:
        MimicsError: when the table has no run of ``scenario``.
    """
    runs = table[(table["scenario"] == scenario) & np.isfinite(table["wall_time"])]
    if runs.empty:
        raise MimicsError(f"no finished run of the {scenario!r} scenario: no wall time figure")
    fig = _new_figure(width_px, height_px)
    ax = fig.add_subplot()
    params = [json.loads(p) if p else {} for p in runs["parameters"]]
    keys = {k for p in params for k in p} - {"robots", "seed"}
    varying = sorted(k for k in keys if len({json.dumps(p.get(k)) for p in params}) > 1)
    runs = runs.assign(setting=[", ".join(f"{k}={p.get(k)}" for k in varying) for p in params])
    for (algorithm, setting), group in runs.groupby(["algorithm", "setting"]):
        stats = group.groupby("robots")["wall_time"].agg(["mean", "std", "count"]).sort_index()
        robots = stats.index.to_numpy(np.float64)
        label = f"{algorithm}" + (f" ({setting})" if setting else "")
        if len(robots) >= 2:
            slope = np.polyfit(robots, stats["mean"].to_numpy(), 1)[0]
            label += f": {1000 * slope:.3g} ms/robot"
        ax.errorbar(robots, stats["mean"], yerr=stats["std"].fillna(0.0), marker="o", ms=4,
                    capsize=3, label=label)
    sim_time = float(np.nanmedian(runs["sim_time"]))
    top = float(np.nanmax(runs["wall_time"]))
    if math.isfinite(sim_time) and sim_time <= 1.5 * top:
        ax.axhline(sim_time, color="#555555", ls="--", lw=1,
                   label=f"real time ({sim_time:g} s simulated)")
    ax.set_xlabel("number of robots")
    ax.set_ylabel("wall time per run (s)")
    ax.set_ylim(bottom=0)
    ax.set_title(f"Wall time against number of robots: {scenario} scenario, "
                 f"{sim_time:g} s simulated per run (mean and s.d. over seeds)", fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return _save(fig, out)


def battery_plots(directory: str | Path, out: str | Path | None = None
                  ) -> tuple[list[Path], list[str]]:
    """Write a battery's figures into ``out`` (default ``DIRECTORY/plots``).

    Returns:
        The paths written, and one line per figure skipped with the reason.

    Raises:
        MimicsError: not a battery folder, or an unwritable ``out``.
    """
    table = battery_table(directory)
    folder = Path(out) if out is not None else Path(directory) / "plots"
    written = [plot_outcomes(table, folder / "outcomes.png"),
               plot_time_to_goal(table, folder / "time_to_goal.png")]
    skipped: list[str] = []
    try:
        written.append(plot_wall_time_vs_robots(table, folder / "wall_time_vs_robots.png"))
    except MimicsError as exc:
        skipped.append(str(exc))
    return written, skipped
