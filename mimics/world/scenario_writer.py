"""Writing a scenario as the TOML file :mod:`mimics.world.scenario_files` reads back.

:func:`save_scenario_toml` writes any scenario (also one built in Python) so
that loading the file gives an equal scenario; :func:`scenario_to_toml` is
its text.
"""

from __future__ import annotations

import json
import math
from dataclasses import fields
from pathlib import Path
from typing import Any

import tomli_w

from mimics.world.errors import MimicsError, ScenarioError
from mimics.world.robot_types import BUILTIN_ROBOT_TYPES
from mimics.world.scenario import Scenario, Settings


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value)  # JSON string escapes are valid TOML basic strings
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{ " + ", ".join(f"{k} = {_toml_value(v)}" for k, v in value.items()) + " }"
    raise TypeError(f"cannot write {value!r} to TOML")


def scenario_to_toml(scenario: Scenario, map_ref: str | dict[str, str] | None = None) -> str:
    """The TOML text of a scenario, robots as an explicit list (see :func:`save_scenario_toml`).

    ``map_ref`` is written as the ``map`` key instead of the walls themselves.
    """
    type_names = [t.name for t in scenario.types]
    duplicates = {n for n in type_names if type_names.count(n) > 1}
    if duplicates:
        raise ScenarioError(f"scenario {scenario.name!r}: two different robot types are named "
                            f"{sorted(duplicates)[0]!r} (expected unique names to save it)")
    out = [f"name = {_toml_value(scenario.name)}"]
    if map_ref is not None:
        out.append(f"map = {_toml_value(map_ref)}")
    out.append("robots = [")
    for i, (x, y, yaw, v) in enumerate(scenario.stages.tolist()):
        robot = {"type": scenario.robot_type(i).name, "x": x, "y": y, "yaw": yaw, "v": v}
        if scenario.has_goal[i]:
            robot["goal"] = scenario.goals[i].tolist()
        out.append(f"  {_toml_value(robot)},")
    out.append("]")
    out.append("")
    settings = {f.name: getattr(scenario.settings, f.name) for f in fields(Settings)}
    out.append(tomli_w.dumps({"settings": settings}).rstrip())
    custom = {t.name: {k: v for k, v in t.to_dict().items() if k != "name"}
              for t in scenario.types if BUILTIN_ROBOT_TYPES.get(t.name) != t}
    if custom:
        out.append("")
        out.append(tomli_w.dumps({"types": custom}).rstrip())
    if map_ref is None:
        the_map = scenario.map
        out += ["", "[map]", f"name = {_toml_value(the_map.name)}",
                f"bounds = {_toml_value(list(the_map.bounds))}", "segments = ["]
        out += [f"  {_toml_value(row)}," for row in the_map.segments.tolist()]
        out.append("]")
    out += edits_to_toml(scenario.edits)
    return "\n".join(out) + "\n"


def edits_to_toml(edits: tuple[Any, ...]) -> list[str]:
    """Lines of ``[[edits]]`` tables, one per edit in order (none: no lines); each
    float in its shortest exact form, so that reading gives the same numbers."""
    out: list[str] = []
    for edit in edits:
        out += ["", "[[edits]]"]
        out += [f"{name} = {_toml_value(value)}" for name, value in edit.to_dict().items()]
    return out


def save_scenario_toml(scenario: Scenario, path: str | Path,
                       map_file: str | Path | None = None) -> Path:
    """Write a scenario as TOML that reads back into an equal scenario.

    The map is referenced by name when it is an unchanged built-in map
    (``stage:cave``), written to ``map_file`` (a plain map file, referenced
    relative to ``path``) when given, and otherwise written inline.

    Raises:
        ScenarioError: the scenario cannot be written (e.g. two types share a name).
    """
    from mimics.world.map_files import BUILTIN_MAPS, builtin_map, save_map

    path = Path(path)
    map_ref: str | dict[str, str] | None = None
    source = scenario.map.source
    if map_file is not None:
        map_path = Path(map_file)
        save_map(scenario.map, map_path if map_path.is_absolute() else path.parent / map_path)
        map_ref = {"file": map_path.as_posix(), "name": scenario.map.name}
    elif source in BUILTIN_MAPS:
        try:
            if builtin_map(source) == scenario.map and scenario.map.name == builtin_map(
                    source).name:
                map_ref = source
        except MimicsError:
            map_ref = None  # the data is missing here: write the walls inline instead
    text = scenario_to_toml(scenario, map_ref)
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise ScenarioError(f"{path}: cannot write ({exc.strerror})") from None
    return path


