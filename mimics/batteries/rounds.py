"""A stopping rule's rounds in a battery's database: what each cell needs next.

The battery process calls :func:`extend_cell` when a run finishes (and
:func:`extend_all` when a session starts, for rounds a killed battery finished
but did not get to schedule); both list in the database the runs of the next
round that :func:`mimics.batteries.until.cell_progress` asks for. Since that
is computed from the finished runs only, a resumed battery lists exactly the
runs an uninterrupted one would have listed.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mimics.batteries.metrics import row_value
from mimics.batteries.references import algorithm_label
from mimics.batteries.spec import BatterySpec, RunSpec
from mimics.batteries.store import BatteryStore
from mimics.batteries.until import CellProgress, UntilRule, cell_progress, half_width

UNFINISHED = ("pending", "running")


@dataclass(frozen=True)
class Cell:
    """An algorithm x scenario x parameter point of a battery."""

    algorithm_ref: str
    algorithm: str
    scenario_ref: str
    scenario: str
    params: dict[str, Any]

    @property
    def key(self) -> tuple[str, str, str]:
        """How the database tells the cell's runs: references and parameters (JSON)."""
        return self.algorithm_ref, self.scenario_ref, json.dumps(self.params, sort_keys=True)

    @property
    def label(self) -> str:
        """The parameter point as the report shows it."""
        return RunSpec(self.algorithm_ref, self.algorithm, self.scenario_ref, self.scenario,
                       self.params, 0).label

    def run(self, seed: int) -> RunSpec:
        """The cell's run with ``seed``."""
        return RunSpec(self.algorithm_ref, self.algorithm, self.scenario_ref, self.scenario,
                       self.params, seed)


def cells(spec: BatterySpec) -> list[Cell]:
    """The battery's cells, in the order of its runs."""
    return [Cell(algorithm, algorithm_label(algorithm), entry.ref, entry.name, point)
            for algorithm in spec.algorithms for entry in spec.scenarios
            for point in entry.points()]


def cell_values(store: BatteryStore, key: tuple[str, str, str], metric: str
                ) -> dict[int, float]:
    """Seed -> the metric's value (NaN: undefined) of the cell's finished runs."""
    cursor = store.db.execute(
        "SELECT * FROM runs WHERE algorithm_ref = ? AND scenario_ref = ? AND params = ?", key)
    names = [d[0] for d in cursor.description]
    values = {}
    for row in (dict(zip(names, r, strict=True)) for r in cursor):
        if row["state"] not in UNFINISHED:
            values[int(row["seed"])] = row_value(row, metric)
    return values


def extend_cell(store: BatteryStore, cell: Cell, rule: UntilRule) -> list[int]:
    """List the runs of the cell's next round if its current one is over; their ids."""
    progress = cell_progress(cell_values(store, cell.key, rule.metric), rule)
    if progress.complete:
        return []
    return store.add_runs([cell.run(seed) for seed in range(1, progress.scheduled + 1)])


def extend_all(store: BatteryStore, spec: BatterySpec) -> list[int]:
    """:func:`extend_cell` for every cell (a session's start); the ids added."""
    if spec.until is None:
        return []
    return [i for cell in cells(spec) for i in extend_cell(store, cell, spec.until)]


class Rounds:
    """The battery loop's view of the rule: after each finished run, its cell's next round."""

    def __init__(self, store: BatteryStore, spec: BatterySpec) -> None:
        self.store = store
        self.rule = spec.until
        self.cells = {cell.key: cell for cell in cells(spec)} if spec.until else {}

    def after(self, run_id: int) -> list[int]:
        """The ids of the runs listed for the finished run's cell (none without a rule,
        or while its round is still running)."""
        if self.rule is None:
            return []
        row = self.store.db.execute("SELECT algorithm_ref, scenario_ref, params FROM runs "
                                    "WHERE id = ?", (run_id,)).fetchone()
        cell = self.cells.get(tuple(row)) if row else None
        return [] if cell is None else extend_cell(self.store, cell, self.rule)


@dataclass(frozen=True)
class CellStatus:
    """A cell's progress under the stopping rule, for ``battery status`` and the workbench."""

    cell: Cell
    progress: CellProgress
    target: float
    seeds: int  # finished runs of the cell
    current: float  # the half-width over all of them (inf: fewer than two values)
    label: str  # the parameter point as the cell's runs show it

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: names, seeds scheduled and finished, half-width, target, complete."""
        width = self.current
        return {"algorithm": self.cell.algorithm, "scenario": self.cell.scenario,
                "parameters": self.label, "seeds": self.seeds,
                "scheduled": self.progress.scheduled,
                "half_width": None if math.isinf(width) or math.isnan(width) else width,
                "target": self.target, "complete": self.progress.complete,
                "state": self.state}

    @property
    def state(self) -> str:
        """``met`` (the target half-width reached), ``max seeds`` (stopped short of it) or
        ``running`` (more seeds to come)."""
        if not self.progress.complete:
            return "running"
        return "met" if self.progress.target_met else "max seeds"


def until_status(store: BatteryStore, spec: BatterySpec) -> list[CellStatus]:
    """Every cell's progress (empty for a battery without a stopping rule)."""
    rule = spec.until
    if rule is None:
        return []
    found = []
    for cell in cells(spec):
        values = cell_values(store, cell.key, rule.metric)
        listed = store.db.execute("SELECT label FROM runs WHERE algorithm_ref = ? AND "
                                  "scenario_ref = ? AND params = ? LIMIT 1", cell.key).fetchone()
        found.append(CellStatus(cell, cell_progress(values, rule), rule.half_width, len(values),
                                half_width(list(values.values()), rule.metric),
                                listed[0] if listed else cell.label))
    return found


def folder_until_status(folder: str | Path) -> tuple[BatterySpec, list[CellStatus]]:
    """The battery folder's spec and every cell's progress (:func:`until_status`).

    Raises:
        MimicsError: when ``folder`` is not a battery folder.
    """
    store = BatteryStore.open(folder)
    try:
        spec = store.spec()
        return spec, until_status(store, spec)
    finally:
        store.close()
