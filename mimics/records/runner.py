"""Running one simulation from names and recording it: shared by the CLI, the Python
API and batteries."""

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
    if robots is not None and (isinstance(robots, bool) or not isinstance(robots, int)
                               or robots < 1):
        raise MimicsError(f"robots: expected a whole number >= 1, got {robots!r}")
    if time is not None and not (isinstance(time, int | float) and time > 0):
        raise MimicsError(f"time: expected a positive number of simulated seconds, got {time!r}")
    if wall_limit is not None and not wall_limit > 0:
        raise MimicsError(f"wall limit: expected a positive number of seconds, got {wall_limit!r}")
    if policy not in ("abort", "deactivate"):
        raise MimicsError(f"policy: expected abort or deactivate, got {policy!r}")
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


def run_to_folder(sim: Simulation, folder: str | Path, **record_options: Any) -> RunResult:
    """Run ``sim`` to the end and write its records into ``folder``."""
    result = sim.run()
    write_summary(result, Path(folder))
    return result
