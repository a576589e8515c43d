"""Running one simulation from names and recording it: shared by the CLI, the Python
API and batteries."""

from __future__ import annotations

import contextlib
from pathlib import Path
from typing import Any

from mimics.catalog import find_algorithm, load_scenario
from mimics.engine.compiling import heap_frozen
from mimics.engine.outcome import RunResult
from mimics.engine.simulation import Policy, Simulation
from mimics.records.layout import FLUSH_ROWS
from mimics.records.recorder import RobotLogs, RunRecorder
from mimics.records.resources import check_memory
from mimics.world.errors import MimicsError
from mimics.world.limits import (
    MAX_ROBOTS,
    MAX_SEED,
    check_time,
    check_wall_seconds,
    check_whole,
)
from mimics.world.scenario import Scenario
from mimics.world.start_state import validate_scenario


def prepare(scenario: str | Path | Scenario, algorithm: Any, *, robots: int | None = None,
            time: float | None = None, seed: int = 0, policy: Policy = "abort",
            wall_limit: float | None = None, params: dict[str, Any] | None = None,
            observers: tuple[Any, ...] = (), allow_overlap: bool = False) -> Simulation:
    """Build a :class:`Simulation` from names or objects, checking every argument.

    Before anything is allocated: counts and the seed are checked against
    :mod:`mimics.world.limits`, the start state against walls and other robots
    (unless ``allow_overlap``), and the memory the run needs against what the
    machine has (:func:`mimics.records.resources.check_memory`).

    Raises:
        MimicsError: one line naming the argument, the limit or the robots.
    """
    if robots is not None:
        check_whole("robots", robots, 1, MAX_ROBOTS)
    check_whole("seed", seed, 0, MAX_SEED)
    if time is not None:
        check_time("time", time)
    if wall_limit is not None:
        check_wall_seconds("wall_limit", wall_limit)
    if params is not None and not (isinstance(params, dict)
                                   and all(isinstance(key, str) for key in params)):
        raise MimicsError(f"params: expected a dict of scenario parameters by name, got "
                          f"{_shown(params)}")
    if not isinstance(observers, list | tuple):
        raise MimicsError(f"observers: expected a tuple of observers, got {_shown(observers)}")
    if policy not in ("abort", "deactivate"):
        raise MimicsError(f"policy: expected abort or deactivate, got {policy!r}")
    if time is not None and params and "time_limit" in params and params["time_limit"] != time:
        raise MimicsError(f"time={time!r} and params time_limit={params['time_limit']!r}: two "
                          "values for the simulated time; give one")
    # a full collection while the set-up builds 100,000 robots walked the imports' objects
    # too: 26-37 ms, 2-3 ms with them frozen (engine.heap_freeze)
    with heap_frozen():
        built = build_scenario(scenario, robots=robots, params=params,
                               allow_overlap=allow_overlap, seed=seed)
        check_memory(built, time=time)
        if isinstance(algorithm, str | Path):
            name, module = find_algorithm(algorithm, load_limit=wall_limit)
        else:
            name, module = getattr(algorithm, "__name__", "algorithm"), algorithm
        return Simulation(built, module, seed=seed, policy=policy, time_limit=time,
                          wall_limit=wall_limit, observers=observers, algorithm_name=name)


def build_scenario(scenario: str | Path | Scenario, *, robots: int | None = None,
                   params: dict[str, Any] | None = None, allow_overlap: bool = False,
                   seed: int | None = None) -> Scenario:
    """The scenario from a name, a file or an object, its start state checked.

    ``robots`` and ``params`` are scenario parameters, for names and files only;
    ``seed``, the run's, draws the scenario's own randomness (start headings,
    jitter, random placements) unless ``params`` fixes its ``seed``.

    Raises:
        MimicsError: parameters given with a Scenario object, a bad parameter, ``robots``
            and ``params["robots"]`` that differ, or robots starting in collision or
            outside the map (unless ``allow_overlap``).
    """
    params = dict(params or {})
    if robots is not None:
        if "robots" in params and params["robots"] != robots:
            raise MimicsError(f"robots={robots} and params robots={params['robots']!r}: two "
                              "values for the same parameter; give one")
        params["robots"] = robots
    if not isinstance(scenario, Scenario):
        return load_scenario(scenario, allow_overlap=allow_overlap, run_seed=seed, **params)
    if params:
        raise MimicsError("robots/params apply to a scenario name or file, not a Scenario")
    validate_scenario(scenario, f"scenario {scenario.name!r}",
                      allow_overlap=allow_overlap or scenario.settings.allow_overlap)
    return scenario


def run_to_folder(sim: Simulation, folder: str | Path, *, robot_logs: RobotLogs = "auto",
                  every: int = 1, flush_rows: int = FLUSH_ROWS, flush_seconds: float = 10.0,
                  record_scans: bool = False, extra: dict[str, Any] | None = None) -> RunResult:
    """Run ``sim`` to the end, recording it into ``folder``; returns its outcome.

    The folder gets scenario.toml, trajectory.parquet, events.parquet, the
    per-robot logs (``robot_logs``: ``"auto"`` up to 200 robots, ``"on"``,
    ``"off"``), summary.txt, and summary.json last (see
    :mod:`mimics.records.run_folder`). If the run raises (an interrupt, a bug),
    what was recorded is kept, without summary.json, and the exception goes on.

    >>> import tempfile
    >>> sim = prepare("line", "go_to_goal", robots=2, seed=1, params={"random_yaw": False})
    >>> run_to_folder(sim, tempfile.mkdtemp(), robot_logs="off").reached_goal
    2

    Args:
        sim: a simulation that has not started.
        folder: the run folder (created; an earlier run's files in it are replaced).
        robot_logs: per-robot text logs: ``"auto"``, ``"on"`` or ``"off"``.
        every: record every ``every``-th step in full (deactivations and the
            last step always).
        flush_rows: trajectory rows buffered before a part file is written.
        flush_seconds: wall-clock seconds between part files at most.
        record_scans: also record the laser scans in scans.parquet
            (:mod:`mimics.records.scans`).
        extra: keys added to summary.json.

    Raises:
        MimicsError: on a bad option, or when ``sim`` has already started.
    """
    if sim.state.step != 0 or sim.status != "running":
        raise MimicsError("run_to_folder: the simulation has already run; give it a new one")
    recorder = RunRecorder(folder, robot_logs=robot_logs, every=every, flush_rows=flush_rows,
                           flush_seconds=flush_seconds, record_scans=record_scans, extra=extra)
    sim.observers.append(recorder)
    try:
        result = sim.run()
    except BaseException:
        with contextlib.suppress(Exception):  # keep what was recorded; the first error wins
            recorder.close()
        raise
    finally:
        sim.observers.remove(recorder)
    return result


def _shown(value: Any) -> str:
    """A value in an error line: its type, and its text when short."""
    text = repr(value)
    return f"{text} (a {type(value).__name__})" if len(text) <= 60 else f"a {type(value).__name__}"
