"""The parts of a scenario file: its map, robot types, robots (explicit and generated) and
settings, each read strictly (:mod:`mimics.world.scenario_files` puts them together).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from mimics.world.edits import Edit, check_edit_fits, edit_from_dict
from mimics.world.errors import MimicsError, ScenarioError
from mimics.world.limits import MAX_ROBOTS, MAX_SEED
from mimics.world.map_files import load_map, map_from_dict
from mimics.world.maps import Map
from mimics.world.placement import random_placement
from mimics.world.robot_types import RobotType, robot_type_from_dict
from mimics.world.scenario import Settings
from mimics.world.streams import keyed_uniform, stream
from mimics.world.toml_source import TableReader, TomlSource, is_number

MAP_SOURCES = ("file", "builtin", "segments")
MAP_OPTIONS = ("scale", "resolution", "origin", "tolerance", "threshold", "negate", "size",
               "center", "boundary")
ROBOT_KEYS = ("type", "x", "y", "yaw", "v", "goal")
GENERATOR_KEYS = {
    "line": ("count", "start", "step", "goal_offset", "seed"),
    "grid": ("rows", "columns", "origin", "spacing", "goal_offset", "seed"),
    "random": ("count", "region", "min_spacing", "clearance", "seed", "goal_region",
               "max_tries"),
}
MAX_RANDOM_ROBOTS = 10_000  # robots of one random generator


@dataclass
class RobotRows:
    """Robots read so far: rows ``[x, y, yaw, v, gx, gy]``, type names and labels."""

    rows: list[list[float]]
    types: list[str]
    labels: list[str]
    entries: list[int]


def read_map(src: TomlSource, data: Any) -> Map:
    key = ("map",)
    if isinstance(data, str):
        data = {"builtin": data} if data.startswith("stage:") else {"file": data}
    allowed = (*MAP_SOURCES, "bounds", "name", *MAP_OPTIONS)
    table = TableReader(src, key, data, allowed, "a map file name, a built-in map name "
                                             "(stage:cave) or a table")
    given = [k for k in MAP_SOURCES if table.has(k)]
    if len(given) != 1:
        raise src.error(key, f"expected exactly one of {', '.join(MAP_SOURCES)}, got "
                             f"{', '.join(given) or 'none'}")
    options = {k: v for k, v in data.items() if k in MAP_OPTIONS}
    bounds = table.numbers("bounds", 4, what="[xmin, ymin, xmax, ymax]") \
        if table.has("bounds") else None
    try:
        if given[0] == "segments":
            if options:
                raise src.error((*key, next(iter(options))), "import options apply to map "
                                                              "files only")
            inline = {k: v for k, v in data.items() if k in ("segments", "bounds", "name")}
            line = src.line_of(("map", "segments"))
            loaded = map_from_dict(inline, f"{src.path}{f', line {line}' if line else ''}: map")
        elif given[0] == "builtin":
            name = table.string("builtin")
            if not name.startswith("stage:"):
                raise table.fail("builtin", f"expected a built-in map name like 'stage:cave', "
                                            f"got {name!r}")
            loaded = load_map(name, **options)
        else:
            file = Path(table.string("file")).expanduser()
            loaded = load_map(file if file.is_absolute() else src.path.parent / file, **options)
    except ScenarioError:
        raise
    except MimicsError as exc:
        raise src.error((*key, given[0]), str(exc)) from None
    name = table.string("name", loaded.name)
    if bounds is not None or name != loaded.name:
        try:
            loaded = Map(loaded.segments, bounds or loaded.bounds, name=name,
                         source=loaded.source)
        except MimicsError as exc:
            raise table.fail("bounds", str(exc)) from None
    return loaded


def read_types(src: TomlSource, data: Any) -> dict[str, RobotType]:
    if not isinstance(data, dict):
        raise src.error(("types",), f"expected tables [types.NAME], got {data!r}")
    types = {}
    for name, table in data.items():
        if not isinstance(table, dict):
            raise src.error(("types", name), f"expected a table (base = \"Pioneer2DX\" and "
                                              f"overrides), got {table!r}")
        line = src.line_of(("types", name))
        where = f"{src.path}{f', line {line}' if line else ''}: types.{name}"
        if "name" in table:
            raise src.error(("types", name, "name"), "the table's name is the type's name; "
                                                     "remove this key")
        try:
            types[name] = robot_type_from_dict({"name": name, **table}, where)
        except ScenarioError:
            raise
        except (TypeError, ValueError) as exc:
            raise ScenarioError(f"{where}: {exc}") from None
    return types


def _type_of(table: TableReader, known: dict[str, RobotType]) -> tuple[str, RobotType]:
    name = table.string("type")
    if name not in known:
        raise table.fail("type", f"unknown robot type {name!r} (expected one of "
                                 f"{', '.join(known)}, or define it in [types.{name}])")
    return name, known[name]


def _offset_goals(table: TableReader, xy: np.ndarray) -> np.ndarray:
    if not table.has("goal_offset"):
        return np.full((len(xy), 2), np.nan)
    dx, dy = table.numbers("goal_offset", 2, what="[dx, dy]")
    return xy + np.array([dx, dy])


def read_robot(src: TomlSource, index: int, data: Any, known: dict[str, RobotType], map: Map,
                robots: RobotRows, seed: int | None, run_seed: int | None = None) -> None:
    """Read ``robots[index]`` into ``robots``. A generator's randomness draws from ``seed``
    (a ``seed`` parameter) if given, else its own ``seed`` key, else ``run_seed`` (the
    run's, None when the file is ``fixed``), else 0."""
    key = ("robots", index)
    kind = data.get("generator") if isinstance(data, dict) else None
    if kind is None:
        table = TableReader(src, key, data, ROBOT_KEYS)
        name, _ = _type_of(table, known)
        goal = (table.numbers("goal", 2, what="[x, y]") if table.has("goal")
                else (math.nan, math.nan))
        robots.rows.append([table.number("x"), table.number("y"), table.number("yaw", 0.0),
                            table.number("v", 0.0), *goal])
        robots.types.append(name)
        robots.labels.append(f"robots[{index}]")
        robots.entries.append(index)
        return
    if not isinstance(kind, str) or kind not in GENERATOR_KEYS:
        raise src.error((*key, "generator"), f"unknown generator {kind!r} (expected one of "
                                              f"{', '.join(GENERATOR_KEYS)})")
    allowed = ("generator", "type", "yaw", "v", *GENERATOR_KEYS[kind])
    table = TableReader(src, key, data, allowed)
    name, robot_type = _type_of(table, known)
    speed = table.number("v", 0.0)
    if kind == "line":
        count = table.integer("count", 1)
        start = np.array(table.numbers("start", 2, what="[x, y]"))
        step = np.array(table.numbers("step", 2, what="[dx, dy]"))
        xy = start + np.arange(count)[:, None] * step
        yaw = _yaws(table, count, seed, run_seed, index)
        goals = _offset_goals(table, xy)
    elif kind == "grid":
        rows, columns = table.integer("rows", 1), table.integer("columns", 1)
        if rows * columns > MAX_ROBOTS:
            raise table.fail("rows", f"{rows} x {columns} robots, over the limit of {MAX_ROBOTS}")
        origin = np.array(table.numbers("origin", 2, what="[x, y]"))
        spacing = table.data.get("spacing")
        if is_number(spacing):
            dx = dy = float(spacing)
        else:
            dx, dy = table.numbers("spacing", 2, what="a number or [dx, dy]")
        r, c = np.divmod(np.arange(rows * columns), columns)
        xy = origin + np.column_stack([c * dx, r * dy])
        yaw = _yaws(table, len(xy), seed, run_seed, index)
        goals = _offset_goals(table, xy)
    else:
        # placing compares each new robot with every one placed: quadratic, hence its own limit
        count = table.integer("count", 1, maximum=MAX_RANDOM_ROBOTS)
        region = (table.numbers("region", 4, what="[xmin, ymin, xmax, ymax]")
                  if table.has("region") else None)
        yaw_value = table.data.get("yaw", "random")
        fixed_yaw = None if yaw_value == "random" else table.number("yaw")
        spacing = table.number("min_spacing") if table.has("min_spacing") else None
        clearance = table.number("clearance") if table.has("clearance") else None
        for what, value in (("min_spacing", spacing), ("clearance", clearance)):
            if value is not None and value < 0:
                raise table.fail(what, f"expected a distance >= 0 (m), got {value!r}")
        rng = stream(_layout_seed(table, seed, run_seed), "toml.random", index)
        taken = np.array([row[:2] for row in robots.rows]).reshape(-1, 2)
        tries = table.integer("max_tries", 1, 2000, maximum=1_000_000)
        try:
            poses = random_placement(count, robot_type, map, rng, region, spacing, clearance,
                                     fixed_yaw, taken, tries)
            goals = np.full((count, 2), np.nan)
            if table.has("goal_region"):
                goal_region = table.numbers("goal_region", 4, what="[xmin, ymin, xmax, ymax]")
                goals = random_placement(count, robot_type, map,
                                         stream(_layout_seed(table, seed, run_seed),
                                                "toml.random_goals", index),
                                         goal_region, spacing, clearance, 0.0, None, tries)[:, :2]
        except ScenarioError as exc:
            raise src.error(key, str(exc)) from None
        xy, yaw = poses[:, :2], poses[:, 2]
    if len(robots.rows) + len(xy) > MAX_ROBOTS:
        raise src.error(key, f"{len(robots.rows) + len(xy)} robots so far, over the limit of "
                             f"{MAX_ROBOTS}")
    for j in range(len(xy)):
        robots.rows.append([xy[j, 0], xy[j, 1], yaw[j], speed, goals[j, 0], goals[j, 1]])
        robots.types.append(name)
        robots.labels.append(f"robots[{index}] ({kind} robot {j})")
        robots.entries.append(index)


def _layout_seed(table: TableReader, seed: int | None, run_seed: int | None) -> int:
    """The seed a generator draws from: the parameter, its own, the run's, or 0."""
    if seed is not None:
        return seed
    if table.has("seed"):
        return table.integer("seed", 0, maximum=MAX_SEED)
    return 0 if run_seed is None else run_seed


def _yaws(table: TableReader, count: int, seed: int | None, run_seed: int | None,
          index: int) -> np.ndarray:
    """A line or grid generator's headings: a number, or ``"random"``: robot j's heading
    drawn from ``(layout seed, index, j)`` alone."""
    if table.data.get("yaw") == "random":
        return keyed_uniform(_layout_seed(table, seed, run_seed), f"toml.yaw.{index}", count,
                             -math.pi, math.pi)
    return np.full(count, table.number("yaw", 0.0))


def read_settings(src: TomlSource, data: Any, overrides: dict[str, Any]) -> Settings:
    known = tuple(f.name for f in fields(Settings))
    table = TableReader(src, ("settings",), data, known)
    merged = {**table.data, **overrides}
    for name, value in merged.items():
        def fail(message: str, name: str = name) -> ScenarioError:
            if name in overrides:
                return ScenarioError(f"{src.path}: parameter {name}: {message}")
            return src.error(("settings", name), message)

        default = getattr(Settings(), name)
        if isinstance(default, str):
            if not isinstance(value, str):
                raise fail(f"expected a string, got {value!r}")
        else:
            flag = isinstance(default, bool)
            if flag != isinstance(value, bool) or not (flag or isinstance(value, int | float)):
                raise fail(f"expected {'true or false' if flag else 'a number'}, got {value!r}")
        try:
            Settings(**{name: value})  # each field's own range check
        except ScenarioError as exc:
            raise fail(str(exc).split(": ", 1)[-1]) from None
    return Settings(**merged)


def read_edits(src: TomlSource, data: Any, robots: int, bounds: tuple[float, ...]
               ) -> tuple[Edit, ...]:
    """The ``[[edits]]`` tables (``mimics.world.edits``), each checked against the
    scenario's robots and bounds; errors name the file, the line and the field."""
    if not isinstance(data, list):
        raise src.error(("edits",), f"expected a list of edit tables ([[edits]]), got {data!r}")
    edits = []
    for index, entry in enumerate(data):
        line = src.line_of(("edits", index))
        where = f"{src.path}{f', line {line}' if line else ''}: edits[{index}]"
        edit = edit_from_dict(entry, where)
        check_edit_fits(edit, robots, bounds, where)
        edits.append(edit)
    return tuple(edits)
