"""A battery's figures: outcomes and run statuses, time to goal per run, arrival curves,
wall time against robots."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from mimics.interfaces.plots.battery_arrivals import plot_arrivals
from mimics.interfaces.plots.battery_table import battery_table
from mimics.interfaces.plots.battery_time_to_goal import plot_time_to_goal
from mimics.interfaces.plots.figures import _new_figure, _save
from mimics.interfaces.render import STATUS_COLORS
from mimics.world.errors import MimicsError

#: Robot outcomes stacked in the battery outcome plot: (summary column, label, colour).
OUTCOMES = (("reached_goal", "reached goal", STATUS_COLORS["reached_goal"]),
            ("collided_at_end", "collided", STATUS_COLORS["collided"]),
            ("escaped", "escaped", STATUS_COLORS["escaped"]),
            ("stopped_other", "deadlock or error", STATUS_COLORS["deadlock"]),
            ("active_at_end", "active at end", STATUS_COLORS["active"]))
RUN_STATUS_COLORS = {"completed": "#2ca02c", "time_limit": "#1f77b4", "wall_limit": "#ff7f0e",
                     "stopped": "#8c8c8c", "error": "#d62728", "timeout": "#9467bd",
                     "crashed": "#000000", "pending": "#dddddd", "running": "#bcbd22"}

def _combo_labels(table: pd.DataFrame) -> list[tuple[str, str, str]]:
    """The cells, parameter point by parameter point (in the battery's order)."""
    points = list(dict.fromkeys(zip(table["scenario"], table["point"], strict=True)))
    cells = set(zip(table["algorithm"], table["scenario"], table["point"], strict=True))
    algorithms = list(dict.fromkeys(table["algorithm"]))
    return sorted(cells, key=lambda c: (points.index(c[1:]), algorithms.index(c[0])))


def _tick_labels(ax: Any, combos: list[tuple[str, str, str]]) -> None:
    """Cell names under the bars, slanted when many would run into each other."""
    x = np.arange(len(combos))
    if len(combos) <= 4:
        ax.set_xticks(x, [f"{a}\n{s}" + (f"\n{p}" if p else "") for a, s, p in combos],
                      fontsize=8)
    else:
        ax.set_xticks(x, [", ".join(v for v in (a, s, p) if v) for a, s, p in combos],
                      fontsize=7, rotation=35, ha="right", rotation_mode="anchor")


def plot_outcomes(table: pd.DataFrame, out: str | Path | None, *, width_px: int = 1200,
                  height_px: int = 600) -> Path | Figure:
    """Robot outcomes and run statuses per algorithm x scenario x parameter point (``out``
    None: the Figure is returned, not saved).

    Each outcome's bar is the mean over the cell's runs of the fraction of the run's robots
    with that outcome: every run weighs the same, whatever its number of robots.
    """
    combos = _combo_labels(table)
    fig = _new_figure(width_px, height_px)
    left, right = fig.subplots(1, 2, width_ratios=[3, 2])
    x = np.arange(len(combos))
    bottom = np.zeros(len(combos))
    keys = ["algorithm", "scenario", "point"]
    robots = table["robots"].where(table["robots"] > 0)  # a run without robots: no fraction
    fractions = table[keys].assign(**{column: table[column] / robots
                                      for column, _, _ in OUTCOMES})
    groups = table.groupby(keys)
    means = fractions.groupby(keys).mean()
    for column, label, colour in OUTCOMES:
        frac = np.array([_finite(means[column].get(c, 0.0)) for c in combos])
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
    _tick_labels(left, combos)
    left.set_ylim(0, 1.1)
    left.set_ylabel("fraction of a run's robots (mean over runs)")
    left.set_title("Robot outcomes per run, averaged over the runs", fontsize=10)
    _legend_beside(left)
    statuses = sorted(table["status"].unique(), key=lambda s: (s != "completed", s))
    counts = table.groupby([*keys, "status"]).size()
    bottom = np.zeros(len(combos))
    for status in statuses:
        values = np.array([counts.get((*c, status), 0) for c in combos], dtype=float)
        right.bar(x, values, bottom=bottom, label=status, width=0.7,
                  color=RUN_STATUS_COLORS.get(status, "#bcbd22"))
        bottom += values
    _tick_labels(right, combos)
    right.set_ylabel("runs")
    right.set_title("Run statuses", fontsize=10)
    _legend_beside(right)
    return _save(fig, out)


def _finite(value: Any) -> float:
    """A mean, 0 for a cell without a run with robots (NaN)."""
    return float(value) if math.isfinite(float(value)) else 0.0


def _legend_beside(ax: Any) -> None:
    """The legend to the right of the axes, outside them: it never covers a bar or a label
    (the constrained layout makes room for it)."""
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0,
              frameon=False)


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
    """Write a battery's figures into ``out`` (default ``DIRECTORY/plots``): outcomes.png,
    time_to_goal.png (one point per run), arrivals.png (arrival curves) and, with runs of
    the line scenario, wall_time_vs_robots.png.

    Returns:
        The paths written, and one line per figure skipped with the reason.

    Raises:
        MimicsError: not a battery folder, or an unwritable ``out``.
    """
    table = battery_table(directory)
    folder = Path(out) if out is not None else Path(directory) / "plots"
    written = [plot_outcomes(table, folder / "outcomes.png"),
               plot_time_to_goal(table, folder / "time_to_goal.png"),
               plot_arrivals(table, folder / "arrivals.png")]
    skipped: list[str] = []
    try:
        written.append(plot_wall_time_vs_robots(table, folder / "wall_time_vs_robots.png"))
    except MimicsError as exc:
        skipped.append(str(exc))
    return written, skipped
