"""The Python entry point: run one simulation in one call.

>>> import mimics
>>> run = mimics.simulate("line", "go_to_goal", robots=3, time=21.8, seed=1)
>>> run.status, run.reached_goal
('completed', 3)
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from mimics.catalog import find_algorithm, load_scenario
from mimics.engine.outcome import RunResult
from mimics.engine.simulation import Policy, Simulation
from mimics.records.summary import write_summary
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario


def prepare(scenario: str | Path | Scenario, algorithm: Any, *, robots: int | None = None,
            time: float | None = None, seed: int = 0, policy: Policy = "abort",
            wall_limit: float | None = None, params: dict[str, Any] | None = None,
            observers: tuple[Any, ...] = ()) -> Simulation:
    """Build a :class:`Simulation` from names or objects, checking every argument."""
    if robots is not None and (not isinstance(robots, int) or robots < 1):
        raise MimicsError(f"robots: expected a whole number >= 1, got {robots!r}")
    if time is not None and not (isinstance(time, int | float) and time > 0):
        raise MimicsError(f"time: expected a positive number of simulated seconds, got {time!r}")
    if wall_limit is not None and not wall_limit > 0:
        raise MimicsError(f"wall limit: expected a positive number of seconds, got {wall_limit!r}")
    params = dict(params or {})
    if robots is not None:
        params["robots"] = robots
    if isinstance(scenario, Scenario):
        if params:
            raise MimicsError("robots/params apply to a scenario name or file, not a Scenario")
        built = scenario
    else:
        built = load_scenario(scenario, **params)
    if isinstance(algorithm, str | Path):
        name, module = find_algorithm(algorithm)
    else:
        name, module = getattr(algorithm, "__name__", "algorithm"), algorithm
    return Simulation(built, module, seed=seed, policy=policy, time_limit=time,
                      wall_limit=wall_limit, observers=observers, algorithm_name=name)


def simulate(scenario: str | Path | Scenario, algorithm: Any, *, robots: int | None = None,
             time: float | None = None, seed: int = 0, policy: Policy = "abort",
             out: str | Path | None = None, wall_limit: float | None = None,
             params: dict[str, Any] | None = None,
             observers: tuple[Any, ...] = ()) -> RunResult:
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
    """
    sim = prepare(scenario, algorithm, robots=robots, time=time, seed=seed, policy=policy,
                  wall_limit=wall_limit, params=params, observers=observers)
    result = sim.run()
    if out is not None:
        write_summary(result, Path(out))
    return result
