"""Rich tables of a battery's intervals, paired comparisons and costs (for the terminal)."""

from __future__ import annotations

import math
from typing import Any

import pandas as pd
from rich.table import Table

from mimics.batteries.comparison import check_metrics
from mimics.batteries.metrics import METRICS

INTERVALS_TITLE = "Per cell, over finished runs"
INTERVALS_LEGEND = ("means: mean [95% t interval corrected for skewness, Hall 1992]; success: "
                    "proportion [95% Wilson interval]; "
                    "a failed run counts as success 0 and reached 0 and has no other value; "
                    "(n=...) where fewer runs have a value")
COMPARISON_TITLE = "Paired comparison: algorithm - baseline, same scenario, parameters and seed"
COMPARISON_LEGEND = ("rates: difference [95% Newcombe interval], McNemar exact p; means: "
                     "difference [95% t interval], Wilcoxon signed-rank p; p adjusted ({adjust}) "
                     "for the {tests} tests shown; * = the primary metric")
COSTS_TITLE = "Costs (not outcomes, not deterministic): wall and user-code time of done runs"


def number(value: Any, digits: int = 2) -> str:
    """A float for a table: ``-`` for NaN or None."""
    if value is None or value is pd.NA or (isinstance(value, float) and math.isnan(value)):
        return "-"
    return f"{value:.{digits}f}"


def digits_of(metric: str) -> int:
    """Decimals shown for a metric."""
    return 3 if METRICS[metric].cost else 2


def interval_text(estimate: float, low: float, high: float, digits: int, n: int | None = None,
                  what: str = "runs") -> str:
    """``"0.80 [0.49, 0.94]"``; ``"all 20 runs: 0.00"`` for a sample with no spread; the
    estimate alone without an interval; ``"n/a"`` without a value."""
    if math.isnan(estimate):
        return "n/a"
    if math.isnan(low):
        return number(estimate, digits)
    if low == high and n is not None and n >= 2:
        return f"all {n} {what}: {estimate:.{digits}f}"
    return f"{estimate:.{digits}f} [{low:.{digits}f}, {high:.{digits}f}]"


def horizon_note(table: pd.DataFrame) -> str:
    """``" (non-arrivals at the 60 s horizon)"`` for the restricted mean's column."""
    if "horizon" not in table:
        return ""
    horizons = sorted({float(h) for h in table["horizon"].dropna()})
    if not horizons:
        return ""
    shown = ", ".join(f"{h:g}" for h in horizons)
    return f" (non-arrivals at the {shown} s horizon)"


def intervals_rich(cells: pd.DataFrame, metrics: list[str] | None = None,
                   horizon: str = "") -> Table:
    """The per-cell intervals of :func:`~mimics.batteries.comparison.cell_intervals`."""
    chosen = check_metrics(metrics)
    rich = Table(title=INTERVALS_TITLE, header_style="bold", caption=INTERVALS_LEGEND)
    for name in ("algorithm", "scenario", "parameters", "runs / done / failed", *chosen):
        header = name + (horizon if name == "time_to_goal" else "")
        if name in METRICS and METRICS[name].conditional:
            header += f" (of {METRICS[name].conditional})"
        rich.add_column(header, justify="left" if name in ("algorithm", "scenario",
                                                           "parameters") else "right")
    for row in cells.to_dict("records"):
        finished = row["done"] + row["failed"]
        texts = []
        for m in chosen:
            text = interval_text(row[m], row[f"{m}_low"], row[f"{m}_high"], digits_of(m),
                                 row[f"{m}_n"])
            texts.append(text + (f" (n={row[f'{m}_n']})" if 0 < row[f"{m}_n"] < finished
                                 and not text.startswith("all") else ""))
        rich.add_row(row["algorithm"], row["scenario"], row["parameters"],
                     f"{row['runs']} / {row['done']} / {row['failed']}", *texts)
    return rich


def p_text(p: float) -> str:
    """A p-value for a table."""
    return "-" if math.isnan(p) else (f"{p:.2g}" if p >= 1e-4 else "<1e-4")


def comparison_rich(comparison: pd.DataFrame, adjust: str = "holm") -> Table:
    """The paired comparison of :func:`~mimics.batteries.comparison.paired_comparison`."""
    tests = int(comparison["p_value"].notna().sum()) if not comparison.empty else 0
    rich = Table(title=COMPARISON_TITLE, header_style="bold",
                 caption=COMPARISON_LEGEND.format(tests=tests, adjust=adjust))
    for name in ("algorithm", "baseline", "scenario", "parameters", "metric", "pairs",
                 "difference [95% interval]", "p", "p adjusted", "note"):
        rich.add_column(name, justify="right" if name in ("pairs", "p", "p adjusted") else
                        "left")
    for row in comparison.to_dict("records"):
        digits = digits_of(row["metric"])
        rich.add_row(row["algorithm"], row["baseline"], row["scenario"], row["parameters"],
                     row["metric"] + (" *" if row["primary"] else ""), str(row["pairs"]),
                     interval_text(row["mean_difference"], row["ci95_low"], row["ci95_high"],
                                   digits, row["pairs"], "pairs"),
                     p_text(row["p_value"]), p_text(row["p_adjusted"]), row["note"])
    return rich


def costs_rich(costs: pd.DataFrame) -> Table:
    """The cost table of :func:`~mimics.batteries.comparison.cost_table`."""
    rich = Table(title=COSTS_TITLE, header_style="bold")
    for name in ("algorithm", "scenario", "parameters", "done", "wall s / run", "wall s total",
                 "user-code s / run"):
        rich.add_column(name, justify="left" if name in ("algorithm", "scenario",
                                                         "parameters") else "right")
    for row in costs.to_dict("records"):
        rich.add_row(row["algorithm"], row["scenario"], row["parameters"], str(row["done"]),
                     number(row["wall_time_mean"], 3), number(row["wall_time_total"], 1),
                     number(row["user_time_mean"], 3))
    return rich


ARRIVALS_TITLE = ("Arrivals: fraction of goal robots arrived by each share of the horizon "
                  "(Kaplan-Meier over the done runs; non-arrivals censored at the horizon)")
ARRIVAL_SHARES = (0.25, 0.5, 0.75, 1.0)


def arrivals_rich(curves: dict[tuple[str, str, str], Any]) -> Table:
    """The arrival curves of :func:`~mimics.batteries.arrivals.arrival_curves`, read at
    quarters of the horizon."""
    import numpy as np

    rich = Table(title=ARRIVALS_TITLE, header_style="bold")
    for name in ("algorithm", "scenario", "parameters", "runs", "arrived / robots",
                 *(f"by {share:.0%} of horizon" for share in ARRIVAL_SHARES)):
        rich.add_column(name, justify="left" if name in ("algorithm", "scenario",
                                                         "parameters") else "right")
    for (algorithm, scenario, label), curve in curves.items():
        shown = []
        for share in ARRIVAL_SHARES:
            at = share * curve.horizon
            k = int(np.searchsorted(curve.times, at, side="right")) - 1
            shown.append("-" if math.isnan(at) else
                         f"{curve.fraction[k] if k >= 0 else 0.0:.2f} ({at:g} s)")
        rich.add_row(algorithm, scenario, label, str(curve.runs),
                     f"{curve.arrived} / {curve.robots}", *shown)
    return rich


def metric_lines() -> list[str]:
    """``name: description`` of every metric (for help texts and docs)."""
    return [f"{m.name}: {m.description}" for m in METRICS.values()]
