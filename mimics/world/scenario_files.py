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

    [[edits]]                      # a change to the world after `step` steps
    step = 100                     # (mimics.world.edits: move_robot, add_wall,
    kind = "add_wall"              # remove_wall, set_goal, remove_robot)
    rectangle = [4.0, 0.5, 4.5, 1.5]

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

Generators also take ``type``, and ``yaw`` and ``v`` for all their robots;
``yaw = "random"`` gives line and grid robots random headings too.

The run's seed draws the generators' randomness (placements, random goals,
random headings: robot j's heading from its own keyed draw), so repetitions
of a run with other seeds meet other layouts; a generator's own ``seed`` key,
a ``seed`` parameter, or ``fixed = true`` at the top of the file fix the
layout (``fixed``: drawn from seed 0). ``[settings] noise = "off"`` runs every
sensor without noise.

Parameters a battery can sweep (``load_scenario_toml(path, robots=20)``):
``robots`` (keep the first N robots), ``seed`` (of the random generators: a
fixed layout) and every field of ``[settings]``.

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

import tomllib
from dataclasses import fields
from pathlib import Path
from typing import Any

import numpy as np

from mimics.world.errors import ScenarioError, read_input_text
from mimics.world.placement import random_placement
from mimics.world.robot_types import BUILTIN_ROBOT_TYPES
from mimics.world.scenario import Scenario, Settings
from mimics.world.scenario_parts import (
    RobotRows,
    read_edits,
    read_map,
    read_robot,
    read_settings,
    read_types,
)
from mimics.world.scenario_writer import save_scenario_toml, scenario_to_toml
from mimics.world.start_state import (
    TOUCH_EPS,
    Bodies,
    overlapping_robots,
    start_problems,
    touching_walls,
    validate_scenario,
)
from mimics.world.toml_source import TableReader, TomlSource

__all__ = ["TOUCH_EPS", "Bodies", "load_scenario_toml", "overlapping_robots", "random_placement",
           "save_scenario_toml", "scenario_from_toml_text", "scenario_to_toml", "start_problems",
           "touching_walls", "validate_scenario"]

# "run" is the [run] table of a recorded scenario.toml; it is ignored on load.
TOP_KEYS = ("name", "description", "fixed", "map", "types", "robots", "settings", "edits",
            "run")
SWEEPABLE = ("robots", "seed")


def scenario_from_toml_text(text: str, path: str | Path, *, run_seed: int | None = None,
                            **overrides: Any) -> Scenario:
    """Build a scenario from TOML text; ``path`` names it in errors and anchors map files.

    See :func:`load_scenario_toml` for ``run_seed`` and the overrides.
    """
    path = Path(path)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML: {exc}") from None
    src = TomlSource(path, text)
    TableReader(src, (), data, TOP_KEYS)
    settings_keys = tuple(f.name for f in fields(Settings))
    for key in overrides:
        if key not in SWEEPABLE and key not in settings_keys:
            raise ScenarioError(f"{path}: no parameter {key!r} (expected one of "
                                f"{', '.join(SWEEPABLE + settings_keys)})")
    count, seed = overrides.get("robots"), overrides.get("seed")
    fixed = data.get("fixed", False)
    if not isinstance(fixed, bool):
        raise src.error(("fixed",), f"expected true or false, got {fixed!r}")
    if fixed:
        run_seed = None  # the layout does not follow the run's seed
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
    the_map = read_map(src, data["map"])
    known = {**BUILTIN_ROBOT_TYPES, **read_types(src, data.get("types", {}))}
    entries = data.get("robots")
    if not isinstance(entries, list) or not entries:
        raise src.error(("robots",) if "robots" in data else (),
                        "missing key 'robots'" if "robots" not in data
                        else f"expected a non-empty list of robot tables, got {entries!r}")
    robots = RobotRows([], [], [], [])
    for index, entry in enumerate(entries):
        read_robot(src, index, entry, known, the_map, robots, seed, run_seed)
    if count is not None:
        if count > len(robots.rows):
            raise ScenarioError(f"{path}: parameter robots: {count} asked, but the file defines "
                                f"{len(robots.rows)}")
        for part in (robots.rows, robots.types, robots.labels, robots.entries):
            del part[count:]
    settings = read_settings(src, data.get("settings", {}),
                              {k: v for k, v in overrides.items() if k in settings_keys})
    used = list(dict.fromkeys(robots.types))
    type_index = np.array([used.index(t) for t in robots.types], dtype=np.int64)
    rows = np.array(robots.rows, dtype=np.float64)
    edits = read_edits(src, data.get("edits", []), len(rows), the_map.bounds)
    scenario = Scenario(map=the_map, types=tuple(known[t] for t in used), type_index=type_index,
                        stages=rows[:, :4], goals=rows[:, 4:], settings=settings, name=name,
                        parameters=dict(overrides), edits=edits)
    lines = {index: src.line_of(("robots", index)) for index in set(robots.entries)}
    labels = [f"{label} (line {lines[index]})" if lines[index] else label
              for label, index in zip(robots.labels, robots.entries, strict=True)]
    validate_scenario(scenario, str(path), labels)
    return scenario


def load_scenario_toml(path: str | Path, *, run_seed: int | None = None,
                       **param_overrides: Any) -> Scenario:
    """Read a declarative scenario (module docstring) and check it strictly.

    Args:
        path: the ``.toml`` file.
        run_seed: the run's seed: the random generators and random headings draw
            from it, unless the file says ``fixed = true`` (then from 0), a
            generator has its own ``seed``, or ``seed`` is given.
        **param_overrides: ``robots`` (keep the first N robots), ``seed`` (of
            the random generators: a fixed layout), or any field of ``[settings]``.

    Raises:
        ScenarioError: one line naming the file, key, line and what was expected.
    """
    path = Path(path)
    return scenario_from_toml_text(read_input_text(path, "scenario", ScenarioError), path,
                                   run_seed=run_seed, **param_overrides)


def scenario_toml_parameters(path: str | Path) -> dict[str, Any]:
    """The parameters a TOML scenario can be swept over, with their values in the file."""
    scenario = load_scenario_toml(path)
    values = {f.name: getattr(scenario.settings, f.name) for f in fields(Settings)}
    return {"robots": scenario.robot_count, "seed": 0, **values}
