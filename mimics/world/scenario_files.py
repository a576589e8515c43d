"""Declarative scenarios in TOML, strictly checked, and the start-state checks of any scenario.

A scenario file::

    name = "two rooms"             # optional (default: the file's stem)
    map = "rooms.txt"              # a map file (relative to this file) or a built-in
                                   # map such as "stage:cave"

    [[robots]]                     # an explicit robot (yaw in rad, v and goal optional)
    type = "Pioneer2DX"
    x = 1.0
    y = 1.0
    goal = [8.0, 1.0]

    [[robots]]                     # a generator of robots
    generator = "line"
    type = "Small"
    count = 5
    start = [1.0, 2.0]
    step = [0.0, 0.6]
    goal_offset = [7.0, 0.0]

    [types.Small]                  # a robot type: a built-in base plus overrides
    base = "Pioneer2DX"
    width = 0.2

    [settings]                     # any field of mimics.world.scenario.Settings
    time_limit = 120.0

Robots may also be one-line inline tables, ``robots = [{ type = "Pioneer2DX",
x = 1.0, y = 1.0 }, ...]``, the form :func:`save_scenario_toml` writes (in
:mod:`mimics.world.scenario_writer`).
``map`` may also be a table: ``{ file = "plan.svg", scale = 0.01 }`` (plus the
import options of :func:`mimics.world.map_files.load_map`), ``{ builtin =
"stage:hospital" }``, or inline ``{ segments = [[x1, y1, x2, y2], ...], bounds =
[xmin, ymin, xmax, ymax] }``; any of them may override ``bounds``.

Robots are explicit (``type, x, y``, optional ``yaw`` (rad), ``v``, ``goal``)
or generators, which give goals to all their robots or to none:

* ``line``: ``count, start = [x, y], step = [dx, dy]``, optional ``goal_offset``;
* ``grid``: ``rows, columns, origin = [x, y], spacing = d or [dx, dy]``, optional
  ``goal_offset``; rows go along y, columns along x;
* ``random``: ``count``, optional ``region = [xmin, ymin, xmax, ymax]`` (default
  the map bounds), ``min_spacing`` (centre to centre, m), ``clearance`` (from
  walls, m), ``seed``, ``yaw`` (a number or ``"random"``, the default) and
  ``goal_region`` for random goals.

Generators also take ``type``, and ``yaw`` and ``v`` for all their robots.
Parameters a battery can sweep (``load_scenario_toml(path, robots=20)``):
``robots`` (keep the first N robots), ``seed`` (of the random generators) and
every field of ``[settings]``.

Every mistake is one :class:`ScenarioError` line naming the file, the key, the
line where it can be found, and what was expected. :func:`validate_scenario`
runs the start-state checks (robots inside the bounds, not touching walls or
each other, goals inside the bounds) on any scenario, also one built in Python.

>>> import tempfile, pathlib
>>> path = pathlib.Path(tempfile.mkdtemp()) / "s.toml"
>>> _ = path.write_text('''
... map = { segments = [[0.0, 0.0, 10.0, 0.0]], bounds = [-1.0, -1.0, 11.0, 5.0] }
... [[robots]]
... generator = "line"
... type = "Pioneer2DX"
... count = 3
... start = [1.0, 1.0]
... step = [0.0, 1.0]
... goal_offset = [8.0, 0.0]
... ''')
>>> s = load_scenario_toml(path)
>>> s.robot_count, s.goals[2].tolist()
(3, [9.0, 3.0])
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import numpy as np

from mimics.world.errors import MimicsError, ScenarioError, read_input_text
from mimics.world.limits import MAX_ROBOTS, MAX_SEED
from mimics.world.map_files import load_map, map_from_dict
from mimics.world.maps import Map
from mimics.world.robot_types import BUILTIN_ROBOT_TYPES, RobotType, robot_type_from_dict
from mimics.world.scenario import Scenario, Settings
from mimics.world.scenario_writer import save_scenario_toml, scenario_to_toml
from mimics.world.start_state import (
    TOUCH_EPS,
    Bodies,
    overlapping_robots,
    start_problems,
    touching_walls,
    validate_scenario,
)

__all__ = ["TOUCH_EPS", "Bodies", "load_scenario_toml", "overlapping_robots", "random_placement",
           "save_scenario_toml", "scenario_from_toml_text", "scenario_to_toml", "start_problems",
           "touching_walls", "validate_scenario"]

# "run" is the [run] table of a recorded scenario.toml; it is ignored on load.
TOP_KEYS = ("name", "description", "map", "types", "robots", "settings", "run")
MAP_SOURCES = ("file", "builtin", "segments")
MAP_OPTIONS = ("scale", "resolution", "origin", "tolerance", "threshold", "negate", "size",
               "center", "boundary")
ROBOT_KEYS = ("type", "x", "y", "yaw", "v", "goal")
GENERATOR_KEYS = {
    "line": ("count", "start", "step", "goal_offset"),
    "grid": ("rows", "columns", "origin", "spacing", "goal_offset"),
    "random": ("count", "region", "min_spacing", "clearance", "seed", "goal_region",
               "max_tries"),
}
SWEEPABLE = ("robots", "seed")
MAX_RANDOM_ROBOTS = 10_000  # robots of one random generator


def random_placement(count: int, robot_type: RobotType, map: Map, rng: np.random.Generator,
                     region: tuple[float, float, float, float] | None = None,
                     min_spacing: float | None = None, clearance: float | None = None,
                     yaw: float | None = None, others: np.ndarray | None = None,
                     max_tries: int = 2000) -> np.ndarray:
    """``count`` random poses ``(count, 3)`` in free space, apart from each other and ``others``.

    Args:
        count: robots to place.
        robot_type: their type (its size decides what touches).
        map: the walls to keep clear of.
        rng: the seeded generator to draw from.
        region: ``(xmin, ymin, xmax, ymax)`` to draw centres in (default the map
            bounds, less the robot's reach).
        min_spacing: least centre-to-centre distance (default 1.5 robot diagonals).
        clearance: least gap between a robot and a wall (default half the robot's width).
        yaw: everyone's heading, or None for random headings.
        others: ``(k, 2)`` centres already taken (kept ``min_spacing`` away).
        max_tries: draws per robot before giving up.

    Raises:
        ScenarioError: a robot could not be placed.
    """
    half = np.array([robot_type.length / 2]), np.array([robot_type.width / 2])
    diagonal = 2 * math.hypot(robot_type.length / 2, robot_type.width / 2)
    spacing = 1.5 * diagonal if min_spacing is None else min_spacing
    gap = robot_type.width / 2 if clearance is None else clearance
    if region is None:  # keep the whole robot inside the bounds
        inset = diagonal / 2 + gap
        xmin, ymin, xmax, ymax = map.bounds
        region = (xmin + inset, ymin + inset, xmax - inset, ymax - inset)
    x0, y0, x1, y1 = region
    taken = np.zeros((0, 2)) if others is None else np.asarray(others, dtype=float).reshape(-1, 2)
    poses = np.zeros((count, 3))
    batch = 64
    for k in range(count):
        for _ in range(0, max_tries, batch):
            xy = rng.uniform((x0, y0), (x1, y1), size=(batch, 2))
            headings = (np.full(batch, float(yaw)) if yaw is not None
                        else rng.uniform(-np.pi, np.pi, batch))
            ok = np.ones(batch, dtype=bool)
            if len(taken):
                dist = np.hypot(*(xy[:, None, :] - taken[None, :, :]).transpose(2, 0, 1))
                ok &= (dist >= spacing).all(axis=1)
            bodies = Bodies(xy, headings, np.repeat(half[0], batch), np.repeat(half[1], batch))
            touching, _ = touching_walls(bodies, map.segments, grow=gap)
            ok[touching] = False
            if ok.any():
                pick = int(np.flatnonzero(ok)[0])
                poses[k] = (*xy[pick], headings[pick])
                taken = np.vstack([taken, xy[pick]])
                break
        else:
            raise ScenarioError(f"cannot place robot {k + 1} of {count} ({robot_type.name}) after "
                                f"{max_tries} tries in region ({x0:g}, {y0:g}, {x1:g}, {y1:g}) "
                                f"with min_spacing {spacing:g} m and clearance {gap:g} m "
                                "(expected fewer robots, a larger region or smaller spacings)")
    return poses


# -- reading ---------------------------------------------------------------------

class _Source:
    """The file being read: names keys, finds their lines, raises the one-line errors."""

    def __init__(self, path: Path, text: str) -> None:
        self.path = path
        self.lines = text.splitlines()

    def line_of(self, key: tuple[Any, ...]) -> int | None:
        """Best-effort line of a key path like ``("robots", 2, "x")`` or ``("settings", "dt")``."""
        table: tuple[Any, ...] = ()
        aot_seen: dict[str, int] = {}
        header = re.compile(r"^\s*(\[\[?)\s*([A-Za-z0-9_.\"' -]+?)\s*\]\]?\s*(#.*)?$")
        assign = re.compile(r"^\s*(\"[^\"]*\"|[A-Za-z0-9_-]+)\s*=")
        found: int | None = None
        inline_array: tuple[str, int] | None = None  # (key, line) of "key = [" at top level
        for number, line in enumerate(self.lines, start=1):
            head = header.match(line)
            if head and not inline_array:
                parts = tuple(p.strip().strip('"') for p in head.group(2).split("."))
                if head.group(1) == "[[":
                    aot_seen[parts[0]] = aot_seen.get(parts[0], -1) + 1
                    table = (parts[0], aot_seen[parts[0]])
                else:
                    table = parts
                if table == key[:len(table)] and len(table) == len(key):
                    return number
                if table == key[:len(table)]:
                    found = number
                continue
            if inline_array:
                if line.strip().startswith("]"):
                    inline_array = None
                    continue
                name, start = inline_array
                if line.strip().startswith("{") and key[:1] == (name,) and len(key) > 1:
                    index = sum(1 for ln in self.lines[start:number - 1]
                                if ln.strip().startswith("{"))
                    if index == key[1]:
                        return number
                continue
            match = assign.match(line)
            if not match:
                continue
            name = match.group(1).strip('"')
            if table == () and line.rstrip().endswith("[") and name == key[0]:
                inline_array = (name, number)
            if (*table, name) == key[:len(table) + 1] and table == key[:len(table)]:
                return number
        return found

    def error(self, key: tuple[Any, ...], message: str) -> ScenarioError:
        line = self.line_of(key) if key else None
        where = f"{self.path}, line {line}" if line else f"{self.path}"
        name = "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in key).lstrip(".")
        return ScenarioError(f"{where}: {name}: {message}" if name else f"{where}: {message}")


def _is_number(value: Any) -> bool:
    return (isinstance(value, int | float) and not isinstance(value, bool)
            and math.isfinite(value))


class _Reader:
    """Typed access to one table of the file, rejecting unknown keys."""

    def __init__(self, src: _Source, key: tuple[Any, ...], data: Any, allowed: tuple[str, ...],
                 what: str = "a table") -> None:
        if not isinstance(data, dict):
            raise src.error(key, f"expected {what}, got {data!r}")
        for name in data:
            if name not in allowed:
                raise src.error((*key, name), f"unknown key (expected one of "
                                               f"{', '.join(allowed)})")
        self.src, self.key, self.data = src, key, data

    def has(self, name: str) -> bool:
        return name in self.data

    def fail(self, name: str, message: str) -> ScenarioError:
        return self.src.error((*self.key, name), message)

    def number(self, name: str, default: float | None = None) -> float:
        value = self.data.get(name, default)
        if value is None:
            raise self.src.error(self.key, f"missing key {name!r} (expected a number)")
        if not _is_number(value):
            raise self.fail(name, f"expected a number, got {value!r}")
        return float(value)

    def integer(self, name: str, minimum: int, default: int | None = None,
                maximum: int = MAX_ROBOTS) -> int:
        value = self.data.get(name, default)
        if value is None:
            raise self.src.error(self.key, f"missing key {name!r} (expected a whole number)")
        if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
            raise self.fail(name, f"expected a whole number >= {minimum}, got {value!r}")
        if value > maximum:
            raise self.fail(name, f"{value} is over the limit of {maximum}")
        return value

    def numbers(self, name: str, size: int, default: Any = None, what: str = "") -> Any:
        value = self.data.get(name, default)
        shape = what or f"[{', '.join('n' * size)}]"
        if value is None:
            raise self.src.error(self.key, f"missing key {name!r} (expected {shape})")
        if (not isinstance(value, list | tuple) or len(value) != size
                or not all(_is_number(v) for v in value)):
            raise self.fail(name, f"expected {shape}, got {value!r}")
        return tuple(float(v) for v in value)

    def string(self, name: str, default: str | None = None) -> str:
        value = self.data.get(name, default)
        if value is None:
            raise self.src.error(self.key, f"missing key {name!r} (expected a string)")
        if not isinstance(value, str):
            raise self.fail(name, f"expected a string, got {value!r}")
        return value


@dataclass
class _Robots:
    """Robots read so far: rows ``[x, y, yaw, v, gx, gy]``, type names and labels."""

    rows: list[list[float]]
    types: list[str]
    labels: list[str]
    entries: list[int]


def _read_map(src: _Source, data: Any) -> Map:
    key = ("map",)
    if isinstance(data, str):
        data = {"builtin": data} if data.startswith("stage:") else {"file": data}
    allowed = (*MAP_SOURCES, "bounds", "name", *MAP_OPTIONS)
    table = _Reader(src, key, data, allowed, "a map file name, a built-in map name "
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


def _read_types(src: _Source, data: Any) -> dict[str, RobotType]:
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


def _type_of(table: _Reader, known: dict[str, RobotType]) -> tuple[str, RobotType]:
    name = table.string("type")
    if name not in known:
        raise table.fail("type", f"unknown robot type {name!r} (expected one of "
                                 f"{', '.join(known)}, or define it in [types.{name}])")
    return name, known[name]


def _offset_goals(table: _Reader, xy: np.ndarray) -> np.ndarray:
    if not table.has("goal_offset"):
        return np.full((len(xy), 2), np.nan)
    dx, dy = table.numbers("goal_offset", 2, what="[dx, dy]")
    return xy + np.array([dx, dy])


def _read_robot(src: _Source, index: int, data: Any, known: dict[str, RobotType], map: Map,
                robots: _Robots, seed: int | None) -> None:
    key = ("robots", index)
    kind = data.get("generator") if isinstance(data, dict) else None
    if kind is None:
        table = _Reader(src, key, data, ROBOT_KEYS)
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
    table = _Reader(src, key, data, allowed)
    name, robot_type = _type_of(table, known)
    speed = table.number("v", 0.0)
    if kind == "line":
        count = table.integer("count", 1)
        start = np.array(table.numbers("start", 2, what="[x, y]"))
        step = np.array(table.numbers("step", 2, what="[dx, dy]"))
        xy = start + np.arange(count)[:, None] * step
        yaw = np.full(count, table.number("yaw", 0.0))
        goals = _offset_goals(table, xy)
    elif kind == "grid":
        rows, columns = table.integer("rows", 1), table.integer("columns", 1)
        if rows * columns > MAX_ROBOTS:
            raise table.fail("rows", f"{rows} x {columns} robots, over the limit of {MAX_ROBOTS}")
        origin = np.array(table.numbers("origin", 2, what="[x, y]"))
        spacing = table.data.get("spacing")
        if _is_number(spacing):
            dx = dy = float(spacing)
        else:
            dx, dy = table.numbers("spacing", 2, what="a number or [dx, dy]")
        r, c = np.divmod(np.arange(rows * columns), columns)
        xy = origin + np.column_stack([c * dx, r * dy])
        yaw = np.full(len(xy), table.number("yaw", 0.0))
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
        own_seed = table.integer("seed", 0, 0, maximum=MAX_SEED)
        rng = np.random.default_rng([own_seed if seed is None else seed, index])
        taken = np.array([row[:2] for row in robots.rows]).reshape(-1, 2)
        tries = table.integer("max_tries", 1, 2000, maximum=1_000_000)
        try:
            poses = random_placement(count, robot_type, map, rng, region, spacing, clearance,
                                     fixed_yaw, taken, tries)
            goals = np.full((count, 2), np.nan)
            if table.has("goal_region"):
                goal_region = table.numbers("goal_region", 4, what="[xmin, ymin, xmax, ymax]")
                goals = random_placement(count, robot_type, map, rng, goal_region, spacing,
                                         clearance, 0.0, None, tries)[:, :2]
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


def _read_settings(src: _Source, data: Any, overrides: dict[str, Any]) -> Settings:
    known = tuple(f.name for f in fields(Settings))
    table = _Reader(src, ("settings",), data, known)
    merged = {**table.data, **overrides}
    for name, value in merged.items():
        def fail(message: str, name: str = name) -> ScenarioError:
            if name in overrides:
                return ScenarioError(f"{src.path}: parameter {name}: {message}")
            return src.error(("settings", name), message)

        flag = isinstance(getattr(Settings(), name), bool)
        if flag != isinstance(value, bool) or not (flag or isinstance(value, int | float)):
            raise fail(f"expected {'true or false' if flag else 'a number'}, got {value!r}")
        try:
            Settings(**{name: value})  # each field's own range check
        except ScenarioError as exc:
            raise fail(str(exc).split(": ", 1)[-1]) from None
    return Settings(**merged)


def scenario_from_toml_text(text: str, path: str | Path, **overrides: Any) -> Scenario:
    """Build a scenario from TOML text; ``path`` names it in errors and anchors map files.

    See :func:`load_scenario_toml` for the overrides.
    """
    path = Path(path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from None
    src = _Source(path, text)
    _Reader(src, (), data, TOP_KEYS)
    settings_keys = tuple(f.name for f in fields(Settings))
    for key in overrides:
        if key not in SWEEPABLE and key not in settings_keys:
            raise ScenarioError(f"{path}: no parameter {key!r} (expected one of "
                                f"{', '.join(SWEEPABLE + settings_keys)})")
    count, seed = overrides.get("robots"), overrides.get("seed")
    if count is not None and (isinstance(count, bool) or not isinstance(count, int) or count < 1):
        raise ScenarioError(f"{path}: parameter robots: expected a whole number >= 1, got "
                            f"{count!r}")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
        raise ScenarioError(f"{path}: parameter seed: expected a whole number >= 0, got {seed!r}")
    name = data.get("name", path.stem)
    if not isinstance(name, str):
        raise src.error(("name",), f"expected a string, got {name!r}")
    if not isinstance(data.get("description", ""), str):
        raise src.error(("description",), "expected a string")
    if "map" not in data:
        raise src.error((), "missing key 'map' (expected a map file, a built-in map name or a "
                            "[map] table)")
    the_map = _read_map(src, data["map"])
    known = {**BUILTIN_ROBOT_TYPES, **_read_types(src, data.get("types", {}))}
    entries = data.get("robots")
    if not isinstance(entries, list) or not entries:
        raise src.error(("robots",) if "robots" in data else (),
                        "missing key 'robots'" if "robots" not in data
                        else f"expected a non-empty list of robot tables, got {entries!r}")
    robots = _Robots([], [], [], [])
    for index, entry in enumerate(entries):
        _read_robot(src, index, entry, known, the_map, robots, seed)
    if count is not None:
        if count > len(robots.rows):
            raise ScenarioError(f"{path}: parameter robots: {count} asked, but the file defines "
                                f"{len(robots.rows)}")
        for part in (robots.rows, robots.types, robots.labels, robots.entries):
            del part[count:]
    settings = _read_settings(src, data.get("settings", {}),
                              {k: v for k, v in overrides.items() if k in settings_keys})
    used = list(dict.fromkeys(robots.types))
    type_index = np.array([used.index(t) for t in robots.types], dtype=np.int64)
    rows = np.array(robots.rows, dtype=np.float64)
    scenario = Scenario(map=the_map, types=tuple(known[t] for t in used), type_index=type_index,
                        stages=rows[:, :4], goals=rows[:, 4:], settings=settings, name=name,
                        parameters=dict(overrides))
    lines = {index: src.line_of(("robots", index)) for index in set(robots.entries)}
    labels = [f"{label} (line {lines[index]})" if lines[index] else label
              for label, index in zip(robots.labels, robots.entries, strict=True)]
    validate_scenario(scenario, str(path), labels)
    return scenario


def load_scenario_toml(path: str | Path, **param_overrides: Any) -> Scenario:
    """Read a declarative scenario (module docstring) and check it strictly.

    Args:
        path: the ``.toml`` file.
        **param_overrides: ``robots`` (keep the first N robots), ``seed`` (of
            the random generators), or any field of ``[settings]``.

    Raises:
        ScenarioError: one line naming the file, key, line and what was expected.
    """
    path = Path(path)
    return scenario_from_toml_text(read_input_text(path, "scenario", ScenarioError), path,
                                   **param_overrides)


def scenario_toml_parameters(path: str | Path) -> dict[str, Any]:
    """The parameters a TOML scenario can be swept over, with their values in the file."""
    scenario = load_scenario_toml(path)
    values = {f.name: getattr(scenario.settings, f.name) for f in fields(Settings)}
    return {"robots": scenario.robot_count, "seed": 0, **values}


# -- writing ---------------------------------------------------------------------
