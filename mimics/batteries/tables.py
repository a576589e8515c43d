"""Rich tables of a battery's intervals and paired comparisons (for the terminal)."""

from __future__ import annotations

import math
from typing import Any

import pandas as pd
from rich.table import Table

from mimics.batteries.comparison import check_metrics
from mimics.batteries.metrics import METRICS

INTERVALS_TITLE = ("Per cell, over done runs: mean [95% t interval]; success: proportion "
                   "[95% Wilson interval]")
COMPARISON_TITLE = ("Paired comparison: algorithm - baseline on the same scenario, parameters "
                    "and seed; mean difference [95% t interval], Wilcoxon signed-rank p")


def number(value: Any, digits: int = 2) -> str:
    """A float for a table: ``-`` for NaN or None."""
    if value is None or value is pd.NA or (isinstance(value, float) and math.isnan(value)):
        return "-"
    return f"{value:.{digits}f}"


def digits_of(metric: str) -> int:
    """Decimals shown for a metric."""
    return 3 if metric == "wall_time" else 2


def interval_text(estimate: float, low: float, high: float, digits: int) -> str:
    """``"0.80 [0.49, 0.94]"``; the estimate alone without an interval."""
    if math.isnan(estimate):
        return "-"
    if math.isnan(low):
        return number(estimate, digits)
    return f"{estimate:.{digits}f} [{low:.{digits}f}, {high:.{digits}f}]"


def intervals_rich(cells: pd.DataFrame, metrics: list[str] | None = None) -> Table:
    """The per-cell intervals of :func:`~mimics.batteries.comparison.cell_intervals`."""
    chosen = check_metrics(metrics)
    rich = Table(title=INTERVALS_TITLE, header_style="bold")
    for name in ("algorithm", "scenario", "parameters", "runs", "done", *chosen):
        rich.add_column(name, justify="left" if name in ("algorithm", "scenario",
                                                         "parameters") else "right")
    for row in cells.to_dict("records"):
        rich.add_row(row["algorithm"], row["scenario"], row["parameters"], str(row["runs"]),
                     str(row["done"]),
                     *(interval_text(row[m], row[f"{m}_low"], row[f"{m}_high"], digits_of(m))
                       for m in chosen))
    return rich


def comparison_rich(comparison: pd.DataFrame) -> Table:
    """The paired comparison of :func:`~mimics.batteries.comparison.paired_comparison`."""
    rich = Table(title=COMPARISON_TITLE, header_style="bold")
    for name in ("algorithm", "baseline", "scenario", "parameters", "metric", "pairs",
                 "difference [95% interval]", "p", "note"):
        rich.add_column(name, justify="right" if name in ("pairs", "p") else "left")
    for row in comparison.to_dict("records"):
        digits = digits_of(row["metric"])
        p = row["p_value"]
        rich.add_row(row["algorithm"], row["baseline"], row["scenario"], row["parameters"],
                     row["metric"], str(row["pairs"]),
                     interval_text(row["mean_difference"], row["ci95_low"], row["ci95_high"],
                                   digits),
                     "-" if math.isnan(p) else (f"{p:.2g}" if p >= 1e-4 else "<1e-4"),
                     row["note"])
    return rich


def metric_lines() -> list[str]:
    """``name: description`` of every metric (for help texts and docs)."""
    return [f"{m.name}: {m.description}" for m in METRICS.values()]
