"""A battery's time to goal: one point per run, a panel per parameter point.

Each run is one point: its restricted mean time to goal, the mean over its
goal robots of their arrival times with each robot that never arrived counted
at the run's horizon (so a run whose robots never arrive scores the horizon,
not nothing). Robots are never pooled across runs: the runs are the
independent replicates. Runs recorded before mimics kept arrival times fall
back to their mean over the robots that arrived, and the figure says so.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from mimics.interfaces.plots.battery_facets import (
    algorithm_colours,
    facets,
    failed_count,
    horizon_text,
    panel_axes,
    panel_size,
    panel_title,
    say_instead,
    suptitle,
)
from mimics.interfaces.plots.figures import _new_figure, _save

_JITTER = 0.18  # half the spread of a column of points, in category widths


def plot_time_to_goal(table: pd.DataFrame, out: str | Path | None, *, width_px: int = 1000,
                      height_px: int | None = None) -> Path | Figure:
    """The restricted mean time to goal of each run, per algorithm, a panel per parameter
    point (and scenario); a box over the runs, the horizon drawn (``out`` None: the Figure
    is returned, not saved; ``height_px`` None: 600, more with many panels)."""
    done = table[table["state"] == "done"]
    recorded = bool(np.isfinite(done["time_to_goal"]).any())
    column = "time_to_goal" if recorded else "time_to_goal_arrived"
    shown = done[np.isfinite(done[column])]
    panels = facets(table)
    fig = _new_figure(*panel_size(len(panels), width_px, height_px))
    if shown.empty:  # a message, not an empty axis
        has_record = bool(done["arrival_times"].notna().any())
        say_instead(fig, "No robot in these runs has a goal:\nno time to goal to plot."
                    if has_record else "No robot reached its goal in these runs:\n"
                    "no time to goal to plot.", "Time to goal per run")
        return _save(fig, out)
    horizons = shown["horizon"].to_numpy(np.float64)
    colours = algorithm_colours(table)
    several = len({s for s, _ in panels}) > 1
    axes = panel_axes(fig, len(panels), sharey=True)
    for k, (ax, (scenario, point)) in enumerate(zip(axes, panels, strict=True)):
        cell = table[(table["scenario"] == scenario) & (table["point"] == point)]
        _draw_panel(ax, cell, column, list(dict.fromkeys(cell["algorithm"])), colours)
        ax.set_title(panel_title(scenario, point, several), fontsize=9)
        if k % 3 == 0:
            ax.set_ylabel(f"restricted mean time to goal (s),\nnon-arrivals counted at "
                          f"{horizon_text(horizons)}" if recorded else
                          "mean time to goal of the robots\nthat arrived (s)", fontsize=8)
    if recorded:
        title = ("Restricted mean time to goal, one point per run (n = runs)\nthe mean over "
                 f"its goal robots, non-arrivals counted at {horizon_text(horizons)} (dashed); "
                 "hollow: some robots never arrived")
    else:
        title = ("Mean time to goal of the robots that arrived, one point per run (n = runs)\n"
                 "conditional on arriving: these runs were recorded before mimics kept arrival "
                 "times, so robots that never arrived are not counted")
    suptitle(fig, title)
    return _save(fig, out)


def _draw_panel(ax: Any, cell: pd.DataFrame, column: str, algorithms: list[str],
                colours: dict[str, str]) -> None:
    """One panel: per algorithm a box over its runs, each run a point (hollow when some of
    its goal robots never arrived), the horizon as a dashed line."""
    jitter = np.random.default_rng(0)  # the same spread at every drawing
    labels = []
    for x, algorithm in enumerate(algorithms):
        runs = cell[cell["algorithm"] == algorithm]
        done = runs[runs["state"] == "done"]
        values = done[column].to_numpy(np.float64)
        keep = np.isfinite(values)
        values = values[keep]
        complete = (done["arrived"] >= done["goal_robots"]).to_numpy(bool)[keep]
        if column == "time_to_goal_arrived":
            complete = np.ones(values.size, dtype=bool)  # unknown: drawn alike
        labels.append(_tick_label(algorithm, values.size, failed_count(runs),
                                  len(done) - values.size))
        if not values.size:
            ax.annotate("no data", (x, 0.5), xycoords=("data", "axes fraction"), ha="center",
                        va="center", fontsize=8, color="#777777")
            continue
        ax.boxplot([values], positions=[x], widths=0.6, showfliers=False,
                   boxprops={"color": "#999999"}, whiskerprops={"color": "#999999"},
                   capprops={"color": "#999999"}, medianprops={"color": "#333333"})
        xs = x + jitter.uniform(-_JITTER, _JITTER, values.size)
        colour = colours[algorithm]
        ax.scatter(xs[complete], values[complete], s=14, color=colour, zorder=3)
        ax.scatter(xs[~complete], values[~complete], s=14, facecolors="none",
                   edgecolors=colour, zorder=3)
    for horizon in sorted(set(cell["horizon"].dropna().to_numpy(np.float64).tolist())):
        ax.axhline(horizon, color="#555555", ls="--", lw=1, zorder=1)
        ax.annotate(f"horizon {horizon:g} s", (1.0, horizon), xycoords=("axes fraction", "data"),
                    ha="right", va="top", fontsize=7, color="#555555", xytext=(-2, -2),
                    textcoords="offset points")
    ax.set_xticks(range(len(algorithms)), labels, fontsize=7)
    ax.set_xlim(-0.6, len(algorithms) - 0.4)
    ax.grid(axis="y", alpha=0.3)


def _tick_label(algorithm: str, shown: int, failed: int, without: int) -> str:
    """The algorithm, its n, and the runs it leaves out (failed, no goal robot or record)."""
    lines = [algorithm, f"n = {shown} run{'s' if shown != 1 else ''}"]
    if failed:
        lines.append(f"{failed} failed")
    if without:
        lines.append(f"{without} without a time")
    return "\n".join(lines)
