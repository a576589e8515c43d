"""A battery's report for the terminal: runs, failures, evidence, costs, warnings."""

from __future__ import annotations

import math
from typing import Any

import pandas as pd
from rich.console import Console
from rich.table import Table

from mimics.batteries.evidence import Evidence
from mimics.batteries.states import FAILED_STATES


def print_report(evidence: Evidence, console: Console, *, only_misbehaving: bool = False,
                 runs: bool = True) -> None:
    """Print the per-run table, the failed runs, the cells a stopping rule left short,
    the intervals per cell, the paired comparison (with two or more algorithms), the
    costs and the identical-seed warnings."""
    from mimics.batteries.arrivals import arrival_curves
    from mimics.batteries.tables import arrivals_rich, costs_rich

    table = evidence.table
    if table.empty:
        console.print("the battery has no runs", markup=False)
        return
    shown = table[table["misbehaving"]] if only_misbehaving else table
    if runs:
        console.print(_runs_rich(shown))
    failures = table[table["state"].isin(FAILED_STATES)]
    if len(failures):
        console.print(f"\n{len(failures)} failed run(s):", style="bold red")
        for row in failures.itertuples():
            console.print(f"  #{row.id} {row.state}: {row.error}", markup=False,
                          highlight=False)
    print_evidence(evidence, console)
    curves = arrival_curves(table)
    if curves:
        console.print(arrivals_rich(curves))
    console.print(costs_rich(evidence.costs))
    print_warnings(evidence, console)


def print_evidence(evidence: Evidence, console: Console) -> None:
    """The failed runs per cell, the unmet cells, the intervals and the comparison."""
    from mimics.batteries.tables import comparison_rich, horizon_note, intervals_rich

    for line in evidence.failed:
        console.print(f"failed: {line}", style="red", markup=False, highlight=False)
    for line in evidence.unmet:
        console.print(f"target not met: {line}", style="yellow", markup=False,
                      highlight=False)
    console.print(intervals_rich(evidence.intervals, evidence.metrics,
                                 horizon_note(evidence.table)))
    if not evidence.comparison.empty:
        console.print(comparison_rich(evidence.comparison, evidence.adjust))


def print_warnings(evidence: Evidence, console: Console) -> None:
    """The identical-seed warnings."""
    for line in evidence.warnings:
        console.print(f"warning: {line}", style="yellow", markup=False, highlight=False)


def _cell(value: Any, digits: int = 0) -> str:
    if value is None or value is pd.NA or (isinstance(value, float) and math.isnan(value)):
        return "-"
    return f"{value:.{digits}f}" if digits else str(value)


def _runs_rich(table: pd.DataFrame) -> Table:
    rich = Table(title="Runs (! = misbehaved)", show_lines=False, header_style="bold")
    for name in ("", "#", "algorithm", "scenario", "parameters", "seed", "state", "reached",
                 "collisions", "deadlocks", "livelocks", "escaped", "exceptions", "wall (s)",
                 "sim (s)"):
        rich.add_column(name, justify="right" if name not in ("algorithm", "scenario",
                                                              "parameters", "state") else "left")
    for row in table.itertuples():
        style = ("red" if row.state in FAILED_STATES else
                 "yellow" if row.misbehaving else "dim" if row.state != "done" else None)
        rich.add_row("!" if row.misbehaving else "", str(row.id), row.algorithm, row.scenario,
                     row.parameters, str(row.seed), row.state, _cell(row.reached_goal),
                     _cell(row.collisions), _cell(row.deadlocks), _cell(row.livelocks),
                     _cell(row.escaped), _cell(row.exceptions), _cell(row.wall_time, 2),
                     _cell(row.sim_time, 1), style=style)
    return rich
