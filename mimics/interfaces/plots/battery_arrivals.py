"""A battery's arrival curves: the fraction of goal robots arrived against time.

One line per algorithm, a panel per parameter point (and scenario): the
Kaplan-Meier estimate over every goal robot of the cell's done runs, each
robot that never arrived censored at its run's horizon
(:mod:`mimics.batteries.arrivals`), with SciPy's pointwise 95% band. A curve
that stays low never hides behind a fast mean of the few that arrived.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from mimics.batteries.arrivals import ArrivalCurve, arrival_curves
from mimics.interfaces.plots.battery_facets import (
    algorithm_colours,
    facets,
    failed_count,
    panel_axes,
    panel_size,
    panel_title,
    say_instead,
    suptitle,
)
from mimics.interfaces.plots.figures import _new_figure, _save

TITLE = ("Arrival curves: fraction of goal robots arrived by time t\n(Kaplan-Meier over every "
         "goal robot of a cell's done runs, n = runs; non-arrivals censored at their run's "
         "horizon, dashed; band: pointwise 95% interval)")


def battery_curves(table: pd.DataFrame) -> dict[tuple[str, str, str], ArrivalCurve]:
    """The arrival curves of a battery table (:func:`~mimics.interfaces.plots.battery_table`),
    keyed by algorithm, scenario and parameter point."""
    return arrival_curves(table.assign(parameters=table["point"]))


def curve_steps(curve: ArrivalCurve) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A curve as steps from time 0 (nothing arrived yet) to its horizon: times, fraction,
    low and high, drawn with ``where="post"``."""
    end = max(curve.horizon, float(curve.times[-1])) if curve.times.size else curve.horizon
    times = np.concatenate([[0.0], curve.times, [end]])
    fraction = np.concatenate([[0.0], curve.fraction, curve.fraction[-1:]
                               if curve.fraction.size else [0.0]])
    low = np.concatenate([[np.nan], curve.low, curve.low[-1:] if curve.low.size else [np.nan]])
    high = np.concatenate([[np.nan], curve.high,
                           curve.high[-1:] if curve.high.size else [np.nan]])
    return times, fraction, low, high


def plot_arrivals(table: pd.DataFrame, out: str | Path | None, *, width_px: int = 1000,
                  height_px: int | None = None) -> Path | Figure:
    """The arrival curves, one line per algorithm, a panel per parameter point, the horizon
    marked (``out`` None: the Figure is returned, not saved; ``height_px`` None: 600, more
    with many panels)."""
    curves = {key: c for key, c in battery_curves(table).items() if c.robots}
    panels = facets(table)
    fig = _new_figure(*panel_size(len(panels), width_px, height_px))
    if not curves:  # a message, not an empty axis
        done = table[table["state"] == "done"]
        text = ("No robot in these runs has a goal:\nno arrival curve to plot."
                if done["arrival_times"].notna().any() else
                "No run with a record of its arrivals (none finished, or recorded before\n"
                "mimics kept arrival times: run the battery again to plot them).")
        say_instead(fig, text, "Arrival curves")
        return _save(fig, out)
    algorithms = list(dict.fromkeys(table["algorithm"]))
    colours = algorithm_colours(table)
    several = len({s for s, _ in panels}) > 1
    axes = panel_axes(fig, len(panels), sharey=True)
    for k, (ax, (scenario, point)) in enumerate(zip(axes, panels, strict=True)):
        cell = table[(table["scenario"] == scenario) & (table["point"] == point)]
        mine = {a: curves[(a, scenario, point)] for a in algorithms
                if (a, scenario, point) in curves}
        _draw_panel(ax, cell, mine, colours)
        ax.set_title(panel_title(scenario, point, several), fontsize=9)
        horizons = sorted({f"{c.horizon:g}" for c in mine.values()})
        ax.set_xlabel(f"time (s); dashed: the {', '.join(horizons)} s horizon" if horizons
                      else "time (s)", fontsize=8)
        if k % 3 == 0:
            ax.set_ylabel("fraction of goal robots arrived", fontsize=8)
    suptitle(fig, TITLE)
    return _save(fig, out)


def _draw_panel(ax: Any, cell: pd.DataFrame, curves: dict[str, ArrivalCurve],
                colours: dict[str, str]) -> None:
    """One panel: a step line and band per algorithm, the horizons dashed, the counts in
    the legend (robots arrived, runs, failed runs left out)."""
    if not curves:
        ax.annotate("no goal robots", (0.5, 0.5), xycoords="axes fraction", ha="center",
                    va="center", fontsize=8, color="#777777")
    for algorithm, curve in curves.items():
        times, fraction, low, high = curve_steps(curve)
        failed = failed_count(cell[cell["algorithm"] == algorithm])
        label = (f"{algorithm}: {curve.arrived}/{curve.robots} arrived, "
                 f"n = {curve.runs} run{'s' if curve.runs != 1 else ''}"
                 + (f", {failed} failed (left out)" if failed else ""))
        colour = colours[algorithm]
        ax.step(times, fraction, where="post", color=colour, lw=1.5, label=label)
        band = np.isfinite(low) & np.isfinite(high)
        ax.fill_between(times, np.where(band, low, fraction), np.where(band, high, fraction),
                        step="post", color=colour, alpha=0.15, lw=0)
    for horizon in sorted({c.horizon for c in curves.values()}):  # named in the x label
        ax.axvline(horizon, color="#555555", ls="--", lw=1)
    ax.set_ylim(-0.02, 1.02)  # a curve that stays at 0 is seen above the axis
    ax.set_xlim(left=0)
    ax.grid(alpha=0.3)
    if curves:
        ax.legend(fontsize=6, loc="lower right", framealpha=0.8)  # where curves are high
