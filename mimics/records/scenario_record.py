"""scenario.toml: exactly what was run, enough to rebuild the scenario and draw its map.

The file follows the layout of declarative scenario files
(:mod:`mimics.world.scenario_files`): ``name``, ``robots`` as an explicit list
of one-line tables (``type``, ``x``, ``y``, ``yaw``, ``v``, ``goal`` when the
robot has one), ``[settings]`` with every field, ``[types.NAME]`` with every
field of every type used (built-in ones too, so the record does not depend on
the library of a later version), and ``[map]`` with its name, bounds and every
wall segment inline (the map is recoverable from the run folder alone). On
top, a ``[run]`` table holds what is not the scenario: seed, algorithm, policy,
time and wall limits, mimics version, creation time and uuid of the run, the
map's source and the scenario's parameters (``[run.parameters]``). The edits of
the world made during the run (``mimics.world.edits``: scheduled in the
scenario, or made live) follow as ``[[edits]]`` tables, each with its step, in
the order they were applied; a run ended from outside (the workbench's Stop, a
wall limit) ends them with an ``end`` edit, its step and status, so that
``mimics run RUN/scenario.toml ALGO --seed S`` re-runs to the same end. Floats are
written in their shortest exact form, so reading gives back the very same
numbers; :func:`read_scenario_record` reads the file without re-checking the
start state (a run may start with robots touching, deactivated at time 0).

>>> import tempfile
>>> from pathlib import Path
>>> from mimics.scenarios.line import scenario
>>> path = Path(tempfile.mkdtemp()) / "scenario.toml"
>>> write_scenario_record(path, scenario(robots=3), {"seed": 1, "algorithm": "go_to_goal"})
>>> back, run = read_scenario_record(path)
>>> back.robot_count, run["seed"], back.goals[2].tolist()
(3, 1, [20.0, 3.0])
"""

from __future__ import annotations

import json
import math
import os
import tomllib
from collections.abc import Iterable
from dataclasses import asdict
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from mimics.world.edits import edit_from_dict
from mimics.world.errors import MimicsError
from mimics.world.maps import Map
from mimics.world.robot_types import robot_type_from_dict
from mimics.world.scenario import Scenario, Settings
from mimics.world.scenario_writer import edits_to_toml


def write_scenario_record(path: Path, scenario: Scenario, run: dict[str, Any]) -> None:
    """Write ``scenario`` and the ``[run]`` table to ``path`` (through a temporary file).

    Args:
        path: the file to write (``scenario.toml`` in a run folder).
        scenario: the scenario that was run.
        run: seed, algorithm and the other facts of the run; None values are left out.
    """
    names = type_names(scenario)
    run_table = {**_toml_ready(run), "map_source": str(scenario.map.source),
                 "parameters": _toml_ready(scenario.parameters)}
    lines = [f"name = {_string(scenario.name)}", "",
             "# one per robot, in the engine's order (robot 0 first); yaw in rad, v in m/s",
             "robots = ["]
    lines += _robot_lines(scenario, names)
    lines += ["]", ""]
    settings = asdict(scenario.settings)
    if isinstance(run.get("time_limit"), int | float):
        # the time the run was given (--time) is the one in force: `mimics run RUN/scenario.toml`
        # then runs as long as the recorded run did
        settings["time_limit"] = float(run["time_limit"])
    tables = {"run": run_table, "settings": settings,
              "types": {name: {k: v for k, v in t.to_dict().items() if k != "name"}
                        for name, t in zip(names, scenario.types, strict=True)}}
    lines.append(tomli_w.dumps(tables))
    world = scenario.map
    lines += ["[map]", f"name = {_string(world.name)}", f"bounds = {_numbers(world.bounds)}",
              "# wall segments [x1, y1, x2, y2] (m)", "segments = ["]
    lines += [f"  {_numbers(s)}," for s in world.segments.tolist()]
    lines.append("]")
    lines += _edit_lines(scenario)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text("\n".join(lines) + "\n")
    os.replace(tmp, path)


def _edit_lines(scenario: Scenario) -> list[str]:
    """The ``[[edits]]`` tables; a recorded end is introduced by a comment giving its time."""
    lines: list[str] = []
    for edit in scenario.edits:
        table = edits_to_toml((edit,))
        if edit.kind == "end":
            seconds = edit.step * scenario.settings.dt  # the engine's own time of that step
            table.insert(1, f"# the run ended here ({edit.status}, t = {seconds:g} s): a re-run "
                            "of this file ends the same way")
        lines += table
    return lines


def _robot_lines(scenario: Scenario, names: list[str]) -> list[str]:
    """One inline table per robot: ``  { type = "T", x = 1.0, y = 2.0, yaw = 0.0, v = 0.0 },``
    and ``goal = [gx, gy]`` before the brace when it has one.

    Made from flat lists of Python floats (``tolist`` of each column: floats are not
    tracked by the garbage collector, unlike a list per robot, whose 100,000 survivors
    set off full collections in a process holding the compiled kernels) with ``repr``
    inlined: 100,000 robots in about 0.27 s rather than 0.33 s.
    """
    types = [f"  {{ type = {_string(name)}, x = " for name in names]
    stages, goals = scenario.stages, scenario.goals
    lines = []
    for kind, x, y, yaw, v, goal, gx, gy in zip(
            scenario.type_index.tolist(), stages[:, 0].tolist(), stages[:, 1].tolist(),
            stages[:, 2].tolist(), stages[:, 3].tolist(), scenario.has_goal.tolist(),
            goals[:, 0].tolist(), goals[:, 1].tolist(), strict=True):
        end = f", goal = [{gx!r}, {gy!r}] }}," if goal else " },"
        lines.append(f"{types[kind]}{x!r}, y = {y!r}, yaw = {yaw!r}, v = {v!r}{end}")
    return lines


def type_names(scenario: Scenario) -> list[str]:
    """The names the record gives the scenario's types: their own, made unique if needed
    (a second type named ``X`` becomes ``X#2``)."""
    names: list[str] = []
    for t in scenario.types:
        name, k = t.name, 1
        while name in names:
            k += 1
            name = f"{t.name}#{k}"
        names.append(name)
    return names


def read_scenario_record(path: Path) -> tuple[Scenario, dict[str, Any]]:
    """The scenario and the ``[run]`` table stored in ``path``.

    Raises:
        MimicsError: naming the file, when it is missing, not TOML or not a run's record.
    """
    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise MimicsError(f"{path}: cannot read ({exc.strerror})") from None
    except UnicodeDecodeError as exc:
        raise MimicsError(f"{path}: not a run's scenario record (not UTF-8 text: "
                          f"{exc.reason})") from None
    except tomllib.TOMLDecodeError as exc:
        raise MimicsError(f"{path}: not valid TOML ({exc})") from None
    if not isinstance(data.get("run"), dict):
        raise MimicsError(f"{path}: not a run's scenario record (no [run] table)")
    try:
        return _scenario_from(data), dict(data["run"])
    except (KeyError, TypeError, ValueError, IndexError) as exc:
        raise MimicsError(f"{path}: malformed scenario record ({type(exc).__name__}: "
                          f"{exc})") from None


def _scenario_from(data: dict[str, Any]) -> Scenario:
    run = data["run"]
    map_data = data["map"]
    world = Map(np.array(map_data["segments"], dtype=np.float64).reshape(-1, 4),
                tuple(map_data["bounds"]), map_data.get("name", "map"),
                run.get("map_source", ""))
    names = list(data["types"])
    types = tuple(robot_type_from_dict({"name": name, **table}, f"types.{name}")
                  for name, table in data["types"].items())
    robots = data["robots"]
    stages = np.array([[r["x"], r["y"], r.get("yaw", 0.0), r.get("v", 0.0)] for r in robots],
                      dtype=np.float64).reshape(-1, 4)
    goals = np.array([r.get("goal", [math.nan, math.nan]) for r in robots], dtype=np.float64)
    type_index = np.array([names.index(r["type"]) for r in robots], dtype=np.int64)
    edits = tuple(edit_from_dict(entry, f"edits[{k}]")
                  for k, entry in enumerate(data.get("edits", [])))
    return Scenario(map=world, types=types, type_index=type_index, stages=stages,
                    goals=goals.reshape(-1, 2), settings=Settings.from_dict(data["settings"]),
                    name=data["name"], parameters=dict(run.get("parameters", {})), edits=edits)


def _toml_ready(values: dict[str, Any]) -> dict[str, Any]:
    """Values TOML can hold: None left out, NumPy scalars unwrapped, others as text."""
    ready: dict[str, Any] = {}
    for key, value in values.items():
        if value is None:
            continue
        if hasattr(value, "item") and np.ndim(value) == 0:
            value = value.item()
        if isinstance(value, dict):
            value = _toml_ready(value)
        elif isinstance(value, list | tuple):
            items = [v.item() if hasattr(v, "item") else v for v in value]
            value = items if all(isinstance(v, bool | int | float | str) for v in items) \
                else str(value)
        elif not isinstance(value, bool | int | float | str):
            value = str(value)
        ready[str(key)] = value
    return ready


def _string(text: str) -> str:
    """A TOML basic string (JSON's escapes are valid TOML)."""
    return json.dumps(text)


def _number(value: float) -> str:
    """A float in TOML, exactly (``repr`` is the shortest exact form; TOML reads it back)."""
    return repr(float(value))


def _numbers(values: Iterable[float]) -> str:
    return "[" + ", ".join(_number(v) for v in values) + "]"
