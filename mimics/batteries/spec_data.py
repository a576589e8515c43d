"""A battery's spec as plain data: its scenarios, its runs, and its JSON for the store.

:mod:`mimics.batteries.spec` reads and checks battery files into these.
"""

from __future__ import annotations

import itertools
import json
import re
from dataclasses import asdict, dataclass, field
from typing import Any

from mimics.batteries.references import algorithm_label
from mimics.batteries.until import UntilRule

DEFAULT_TIMEOUT = 300.0
_SAFE = re.compile(r"[^A-Za-z0-9._=+-]+")


@dataclass(frozen=True)
class ScenarioEntry:
    """One ``[[scenarios]]`` table: a scenario and its parameters (lists sweep).

    Attributes:
        ref: the built-in name, or the absolute path of a ``.py``/``.toml`` file.
        name: the display name (the built-in name or the file's stem).
        params: parameter values as written; a list is a sweep.
    """

    ref: str
    name: str
    params: dict[str, Any] = field(default_factory=dict)

    def points(self) -> list[dict[str, Any]]:
        """Every parameter point of the sweep, in file order."""
        keys = list(self.params)
        values = [v if isinstance(v, list) else [v] for v in self.params.values()]
        return [dict(zip(keys, combo, strict=True)) for combo in itertools.product(*values)]


@dataclass(frozen=True)
class RunSpec:
    """One run of a battery: an algorithm on a scenario at a parameter point with a seed."""

    algorithm_ref: str
    algorithm: str
    scenario_ref: str
    scenario: str
    params: dict[str, Any]
    seed: int

    @property
    def label(self) -> str:
        """The parameter point as ``"robots=10, spacing=2.0"`` (empty without parameters)."""
        return ", ".join(f"{k}={value_text(v)}" for k, v in self.params.items())

    def folder_name(self, run_id: int) -> str:
        """The run's folder name inside ``runs/``: id, names, parameters and seed."""
        params = "-".join(f"{k}={value_text(v)}" for k, v in self.params.items())
        parts = [f"{run_id:05d}", self.algorithm, self.scenario, params, f"s{self.seed}"]
        name = _SAFE.sub("_", "-".join(p for p in parts if p))
        return name if len(name) <= 120 else f"{name[:110]}-s{self.seed}"


@dataclass(frozen=True)
class BatterySpec:
    """A validated battery: what to run and how.

    Attributes:
        algorithms: built-in names or absolute ``.py`` paths.
        scenarios: the ``[[scenarios]]`` tables.
        seeds: the seeds of every combination.
        time: simulated seconds per run (None: each scenario's own limit).
        timeout: wall-clock seconds per run; past it the run is stopped (and
            its worker killed if it does not stop by itself) and recorded ``timeout``.
        policy: ``"abort"`` or ``"deactivate"`` on exceptions in user code.
        robot_logs: per-robot text logs in run folders (``"off"``, ``"auto"``, ``"on"``).
        record_every: record every n-th step of the trajectory.
        record_scans: also record the laser scans in each run folder.
        name: a label for the battery.
        source: the file it was read from ("" when built in memory).
        until: the stopping rule (None: a fixed battery); ``seeds`` is then its first
            round, 1..min_seeds, and later rounds are added as cells finish them.
        ros_timeout: ``ros:`` algorithms' lockstep time-out in seconds (None: 10 s).
        primary: the metric the battery was run to answer, marked in comparisons (""
            when the file names none: ``success`` where robots have goals).
        isolation: ``"worker"`` (a worker runs many runs) or ``"run"`` (a fresh process
            per run; :mod:`mimics.batteries.isolation`).
        sandbox: ``""`` (none) or ``"bwrap"`` (each run under bubblewrap).
    """

    algorithms: tuple[str, ...]
    scenarios: tuple[ScenarioEntry, ...]
    seeds: tuple[int, ...] = (1,)
    time: float | None = None
    timeout: float = DEFAULT_TIMEOUT
    policy: str = "abort"
    robot_logs: str = "off"
    record_every: int = 1
    record_scans: bool = False
    name: str = ""
    source: str = ""
    until: UntilRule | None = None
    ros_timeout: float | None = None
    primary: str = ""
    isolation: str = "worker"
    sandbox: str = ""

    def runs(self) -> list[RunSpec]:
        """Every run, in order: algorithm, scenario, parameter point, seed."""
        runs = []
        for algorithm in self.algorithms:
            label = algorithm_label(algorithm)
            for entry in self.scenarios:
                for point in entry.points():
                    runs.extend(RunSpec(algorithm, label, entry.ref, entry.name, point, seed)
                                for seed in self.seeds)
        return runs

    def to_json(self) -> str:
        """The spec as JSON (stored in the battery's database)."""
        return json.dumps(asdict(self), sort_keys=True)

    @classmethod
    def from_json(cls, text: str) -> BatterySpec:
        """The spec stored by :meth:`to_json`."""
        data = json.loads(text)
        scenarios = tuple(ScenarioEntry(**s) for s in data.pop("scenarios"))
        until = data.pop("until", None)
        return cls(algorithms=tuple(data.pop("algorithms")), scenarios=scenarios,
                   seeds=tuple(data.pop("seeds")),
                   until=None if until is None else UntilRule(**until), **data)


def value_text(value: Any) -> str:
    """A parameter's value as battery files and run folders show it."""
    return json.dumps(value) if isinstance(value, list | dict) else str(value)
