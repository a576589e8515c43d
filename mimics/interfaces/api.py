"""The Python entry point: run one simulation in one call.

>>> import mimics
>>> run = mimics.simulate("line", "go_to_goal", robots=3, time=21.8, seed=1,
...                       params={"random_yaw": False})  # facing their goals
>>> run.status, run.reached_goal
('completed', 3)
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from mimics.engine.outcome import RunResult
from mimics.engine.simulation import Policy
from mimics.records.runner import prepare, run_to_folder
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario


def simulate(scenario: str | Path | Scenario, algorithm: Any, *, robots: int | None = None,
             time: float | None = None, seed: int = 0, policy: Policy = "abort",
             out: str | Path | None = None, wall_limit: float | None = None,
             params: dict[str, Any] | None = None,
             observers: tuple[Any, ...] = (), record_scans: bool = False,
             allow_overlap: bool = False) -> RunResult:
    """Run one simulation and return its outcome; with ``out``, also write its folder.

    Args:
        scenario: a built-in name (``"line"``), a ``.py``/``.toml`` file, or a Scenario.
        algorithm: a built-in name, a ``.py`` file, or a module/function/class.
        robots: shorthand for the scenario parameter ``robots``.
        time: simulated seconds (default: the scenario's time limit).
        seed: seeds every random draw; same inputs and seed give identical results.
        policy: ``"abort"`` or ``"deactivate"`` on exceptions in user code.
        out: a folder for the run's records (summary.json and logs).
        wall_limit: stop after this many wall-clock seconds.
        params: other scenario parameters.
        observers: extra observers (e.g. a live view).
        record_scans: with ``out``, also record the laser scans (scans.parquet).
        allow_overlap: keep robots that start touching walls or each other, or outside
            the map (by default the scenario is refused, naming them).
    """
    sim = prepare(scenario, algorithm, robots=robots, time=time, seed=seed, policy=policy,
                  wall_limit=wall_limit, params=params, observers=observers,
                  allow_overlap=allow_overlap)
    if out is None:
        if record_scans:
            raise MimicsError("record_scans: give out=FOLDER too (the scans go in the run folder)")
        return sim.run()
    return run_to_folder(sim, out, record_scans=record_scans)
