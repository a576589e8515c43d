"""Everything a battery shows a reader, gathered once for every interface.

``mimics battery report`` and ``compare``, the notebook's BatteryView and the
workbench's evidence route all read a battery through :func:`battery_evidence`,
so that they say the same thing: the cells' intervals, the paired comparison
with its multiplicity adjustment and primary metric, the failed runs named,
the cells a stopping rule left short of their target, the costs apart from
the outcomes, and the seeds that gave identical runs.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import pandas as pd

from mimics.batteries.comparison import (
    cell_intervals,
    check_metrics,
    cost_table,
    failed_runs_lines,
    paired_comparison,
)
from mimics.batteries.seed_warnings import identical_seed_warnings

if TYPE_CHECKING:
    from mimics.batteries.rounds import CellStatus
    from mimics.batteries.until import UntilRule


@dataclass(frozen=True)
class Evidence:
    """A battery's evidence (DataFrames empty and lists empty where there is none).

    Attributes:
        table: one row per run (:func:`mimics.batteries.report.runs_table`).
        metrics: the metrics shown, the primary first.
        primary: the metric the battery answers ("" when none applies).
        intervals: :func:`~mimics.batteries.comparison.cell_intervals`.
        comparison: :func:`~mimics.batteries.comparison.paired_comparison` (empty with one
            algorithm).
        costs: :func:`~mimics.batteries.comparison.cost_table`.
        failed: the failed runs of each cell, a line each.
        unmet: cells a stopping rule stopped at ``max_seeds`` short of its target.
        warnings: cells whose seeds gave identical runs.
        adjust: the p-value adjustment of the comparison.
        tests: p-values the comparison made (what ``adjust`` adjusts for).
        until: the battery's stopping rule (None: a fixed battery).
        cells: each cell's progress under it (empty without one).
    """

    table: pd.DataFrame
    metrics: list[str]
    primary: str
    intervals: pd.DataFrame
    comparison: pd.DataFrame
    costs: pd.DataFrame
    failed: list[str]
    unmet: list[str]
    warnings: list[str]
    adjust: str
    tests: int
    until: UntilRule | None = None
    cells: list[CellStatus] = field(default_factory=list)


def default_primary(table: pd.DataFrame, named: str = "") -> str:
    """The battery file's ``primary``, else ``success`` where some robot has a goal."""
    if named:
        return named
    goals = table["goal_robots"].dropna() if "goal_robots" in table else pd.Series(dtype=int)
    return "success" if len(goals) and (goals > 0).any() else ""


def battery_evidence(folder: str | Path, *, baseline: str | None = None,
                     metrics: list[str] | None = None, exclude_failed: bool = False,
                     adjust: str = "holm", method: str = "t",
                     table: pd.DataFrame | None = None) -> Evidence:
    """The evidence of the battery in ``folder``.

    Args:
        folder: a battery folder.
        baseline: the algorithm the others are compared with (default: the first).
        metrics: the metrics to show (default: the primary and the default set).
        exclude_failed: leave failed runs out of rates and comparisons, on purpose.
        adjust: ``"holm"`` (default), ``"bh"`` or ``"none"``.
        method: ``"t"`` or ``"bootstrap"`` (BCa) for the intervals of means.
        table: the runs table, when the caller has read it already.

    Raises:
        MimicsError: for a folder that is no battery, or an unknown option value.
    """
    from mimics.batteries.report import runs_table
    from mimics.batteries.rounds import folder_until_status

    chosen = check_metrics(metrics)
    if table is None:
        table = runs_table(folder)
    spec, statuses = folder_until_status(folder)
    primary = default_primary(table, spec.primary)
    if metrics is None:  # the primary first, and the stopping rule's metric
        wanted = [primary] if primary else []
        if spec.until is not None:
            wanted.append(spec.until.metric)
        chosen = list(dict.fromkeys([*wanted, *chosen]))
    unmet = [f"{s.cell.algorithm} x {s.cell.scenario}" + (f" ({s.label})" if s.label else "")
             + f": stopped at max_seeds = {s.progress.scheduled} with a half-width of "
             f"{s.progress.half_width:.3g}, short of the target {s.target:g}"
             for s in statuses if s.state == "max seeds"]
    if table.empty:
        empty = pd.DataFrame()
        return Evidence(table, chosen, primary, empty, empty, empty, [], unmet, [], adjust, 0,
                        spec.until, statuses)
    comparison = paired_comparison(table, baseline, chosen, exclude_failed=exclude_failed,
                                   adjust=adjust, primary=primary, method=method)
    tests = int(comparison["p_value"].notna().sum())
    return Evidence(table, chosen, primary,
                    cell_intervals(table, chosen, exclude_failed=exclude_failed, method=method),
                    comparison, cost_table(table), failed_runs_lines(table), unmet,
                    identical_seed_warnings(table), adjust, tests, spec.until, statuses)
