"""Panels for the battery figures: one per parameter point (and scenario), shared colours."""

from __future__ import annotations

import math
import textwrap
from typing import Any

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from mimics.batteries.tasks import FAILED_STATES

#: The most panels in one row of a figure.
COLUMNS = 3


def facets(table: pd.DataFrame) -> list[tuple[str, str]]:
    """The (scenario, parameter point) pairs of a battery table, in the order of its runs."""
    return list(dict.fromkeys(zip(table["scenario"], table["point"], strict=True)))


def panel_title(scenario: str, point: str, several_scenarios: bool) -> str:
    """A panel's title: the parameter point, with its scenario when there are several."""
    if not several_scenarios:
        return point or scenario
    return f"{scenario}: {point}" if point else scenario


def panel_size(count: int, width_px: int, height_px: int | None) -> tuple[int, int]:
    """The figure's size: the height grows with the rows of panels unless given."""
    rows = max(1, math.ceil(count / COLUMNS))
    return width_px, height_px if height_px is not None else max(600, 300 * rows)


def panel_axes(fig: Figure, count: int, **shared: Any) -> list[Any]:
    """``count`` axes on a grid of at most :data:`COLUMNS` per row (extra cells hidden)."""
    columns = min(max(count, 1), COLUMNS)
    rows = max(1, math.ceil(count / columns))
    grid = np.atleast_1d(fig.subplots(rows, columns, squeeze=False, **shared)).ravel()
    for ax in grid[count:]:
        ax.set_axis_off()
    return list(grid[:count])


def algorithm_colours(table: pd.DataFrame) -> dict[str, str]:
    """One colour per algorithm, the same in every panel and figure."""
    palette = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2",
               "#7f7f7f", "#bcbd22", "#17becf")
    names = list(dict.fromkeys(table["algorithm"]))
    return {name: palette[k % len(palette)] for k, name in enumerate(names)}


def say_instead(fig: Figure, text: str, title: str) -> None:
    """A message where the figure would be, instead of an empty axis."""
    ax = fig.add_subplot()
    ax.set_axis_off()
    ax.text(0.5, 0.5, text, ha="center", va="center", fontsize=12, transform=ax.transAxes)
    ax.set_title(title, fontsize=10)


def horizon_text(horizons: np.ndarray) -> str:
    """``"the 60 s horizon"``, or the range when runs had different horizons."""
    finite = horizons[np.isfinite(horizons)]
    if not finite.size:
        return "the horizon"
    low, high = float(finite.min()), float(finite.max())
    return f"the {low:g} s horizon" if low == high else f"each run's horizon ({low:g}-{high:g} s)"


def failed_count(cell: pd.DataFrame) -> int:
    """Runs of a cell that ended in error, time-out or crash (pending runs are not failed)."""
    return int(cell["state"].isin(FAILED_STATES).sum())


def suptitle(fig: Figure, text: str) -> None:
    """The figure's title, each line wrapped to the figure's width (none cut off)."""
    width = max(40, int(fig.get_figwidth() * fig.dpi / 7.5))  # characters of 9-point text
    lines = [wrapped for line in text.split("\n")
             for wrapped in textwrap.wrap(line, width, break_on_hyphens=False)]
    fig.suptitle("\n".join(lines), fontsize=9)
