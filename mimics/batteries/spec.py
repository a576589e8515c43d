"""Battery files: reading, strict validation and expansion into runs.

A battery file (TOML) names algorithms, scenarios, seeds and settings; every
combination is one run::

    [battery]
    algorithms = ["go_to_goal", "my_algos/avoid.py"]   # names or paths (relative to the file)
    seeds = 30            # a count (seeds 1..30) or a list [1, 5, 9]
    time = 60.0           # simulated seconds per run (default: the scenario's)
    timeout = 300         # wall-clock seconds per run
    policy = "abort"      # or "deactivate"
    robot_logs = "off"    # per-robot text logs in run folders: "off", "auto" or "on"
    record_every = 1      # record every n-th step of the trajectory
    record_scans = false  # also record the laser scans (scans.parquet)
    primary = "success"   # the metric the battery answers, marked in comparisons
    isolation = "worker"  # or "run": a fresh process per run (see batteries.isolation)
    sandbox = "none"      # or "bwrap": each run under bubblewrap (implies isolation = "run")

    [battery.until]       # instead of `seeds`: seeds 1, 2... in rounds until the answer is known
    metric = "time_to_goal"
    half_width = 0.2      # stop a cell when its 95% interval is at most this wide each side
    min_seeds = 20
    max_seeds = 500

    [[scenarios]]
    name = "line"         # a built-in name or a path
    robots = [1, 10, 60]  # any scenario parameter; a list sweeps it

    [[scenarios]]
    name = "cave"

A list sweeps a parameter; to pass one list as a value, wrap it: ``goal =
[[1.0, 2.0]]``. Unknown keys, wrong types, unknown algorithms, scenarios or
scenario parameters are :class:`~mimics.world.errors.MimicsError` lines naming
the file and the key. Runs are listed algorithm by algorithm, then scenario,
parameter point and seed.

>>> spec = spec_from_dict({"battery": {"algorithms": ["go_to_goal"], "seeds": 2},
...                        "scenarios": [{"name": "line", "robots": [1, 3]}]})
>>> [(r.scenario, r.label, r.seed) for r in spec.runs()]
[('line', 'robots=1', 1), ('line', 'robots=1', 2), ('line', 'robots=3', 1), ('line', 'robots=3', 2)]
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path
from typing import Any

from mimics.batteries.isolation import parse_isolation
from mimics.batteries.metrics import METRICS
from mimics.batteries.references import check_algorithms, is_path, resolve

# the spec as plain data lives in spec_data; its names are read from here too
from mimics.batteries.spec_data import DEFAULT_TIMEOUT, BatterySpec, ScenarioEntry, value_text
from mimics.batteries.spec_data import RunSpec as RunSpec
from mimics.batteries.until import parse_until
from mimics.world.errors import MimicsError, read_input_text
from mimics.world.limits import (
    MAX_ROBOTS,
    MAX_SEED,
    MAX_STEPS,
    check_time,
    check_wall_seconds,
    check_whole,
)

BATTERY_KEYS = ("name", "algorithms", "seeds", "time", "timeout", "policy", "robot_logs",
                "record_every", "record_scans", "until", "ros_timeout", "primary", "isolation",
                "sandbox")
TOP_KEYS = ("battery", "scenarios")
POLICIES = ("abort", "deactivate")
ROBOT_LOGS = ("off", "auto", "on")
MAX_RUNS = 1_000_000  # runs of one battery (each is a folder on disk and a database row)


# -- reading and checking ------------------------------------------------------

def load_battery(path: str | Path) -> BatterySpec:
    """Read and validate a battery file.

    Relative algorithm and scenario paths are taken relative to the file.

    Raises:
        MimicsError: one line naming the file, the key and what was expected.
    """
    source = Path(path)
    text = read_input_text(source, "battery")
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise MimicsError(f"{source}: not valid TOML: {exc}") from None
    return spec_from_dict(data, base=source.parent, source=str(source))


def spec_from_dict(data: dict[str, Any], base: str | Path = ".", source: str = "") -> BatterySpec:
    """Validate a parsed battery file (``{"battery": {...}, "scenarios": [...]}``).

    Args:
        data: the parsed TOML.
        base: the folder relative paths are relative to.
        source: the file name used in error messages.

    Raises:
        MimicsError: one line naming the file, the key and what was expected.
    """
    where = f"{source}: " if source else ""
    base = Path(base)

    def fail(message: str) -> MimicsError:
        return MimicsError(f"{where}{message}")

    _no_unknown(data, TOP_KEYS, "the top level", fail)
    table = data.get("battery")
    if not isinstance(table, dict):
        raise fail("missing [battery] table (with at least `algorithms`)")
    _no_unknown(table, BATTERY_KEYS, "[battery]", fail)
    algorithms = check_algorithms(table.get("algorithms"), base, fail)
    until = None
    if "until" in table:
        until = parse_until(table["until"], fail)
        if "seeds" in table:
            raise fail("[battery] seeds: not with [battery.until], which runs seeds 1, 2... "
                       "up to max_seeds (remove one of them)")
        seeds = tuple(range(1, until.min_seeds + 1))
    else:
        seeds = _seeds(table.get("seeds", 1), fail)
    time = table.get("time")
    if time is not None:
        _limited(check_time, "[battery] time", time, fail)
    timeout = table.get("timeout", DEFAULT_TIMEOUT)
    _limited(check_wall_seconds, "[battery] timeout", timeout, fail)
    policy = table.get("policy", "abort")
    if policy not in POLICIES:
        raise fail(f"[battery] policy: expected \"abort\" or \"deactivate\", got {policy!r}")
    robot_logs = table.get("robot_logs", "off")
    if robot_logs not in ROBOT_LOGS:
        raise fail(f"[battery] robot_logs: expected one of {', '.join(ROBOT_LOGS)}, got "
                   f"{robot_logs!r}")
    every = table.get("record_every", 1)
    if isinstance(every, bool) or not isinstance(every, int) or not 1 <= every <= MAX_STEPS:
        raise fail(f"[battery] record_every: expected a whole number from 1 to {MAX_STEPS}, "
                   f"got {every!r}")
    scans = table.get("record_scans", False)
    if not isinstance(scans, bool):
        raise fail(f"[battery] record_scans: expected true or false, got {scans!r}")
    ros_timeout = table.get("ros_timeout")
    if ros_timeout is not None:
        _limited(check_wall_seconds, "[battery] ros_timeout", ros_timeout, fail)
    if ros_timeout is not None and not any(a.startswith(("ros:", "ros2:")) for a in algorithms):
        raise fail("[battery] ros_timeout: only for ros: and ros2: algorithms (ros:PROGRAM "
                   "or ros2:PROGRAM [ARGS...]), and this battery has none")
    name = table.get("name", "")
    if not isinstance(name, str):
        raise fail(f"[battery] name: expected a string, got {name!r}")
    primary = _primary(table.get("primary", ""), fail)
    isolation, sandbox = parse_isolation(table, algorithms, fail)
    scenarios = _scenarios(data.get("scenarios"), base, fail)
    if time is not None:
        for k, entry in enumerate(scenarios, start=1):
            if "time_limit" in entry.params:
                raise fail(f"[battery] time = {time!r} and [[scenarios]] #{k} ({entry.name}) "
                           f"time_limit = {value_text(entry.params['time_limit'])}: two values for "
                           "the simulated time; give one")
    count = len(algorithms) * (until.max_seeds if until else len(seeds)) * sum(
        math.prod(len(v) if isinstance(v, list) else 1 for v in entry.params.values())
        for entry in scenarios)
    if count > MAX_RUNS:
        raise fail(f"{count} runs (algorithms x scenarios x sweeps x seeds), over the limit of "
                   f"{MAX_RUNS} per battery (expected fewer seeds or shorter sweeps)")
    return BatterySpec(algorithms=algorithms, scenarios=scenarios, seeds=seeds,
                       time=None if time is None else float(time), timeout=float(timeout),
                       policy=policy, robot_logs=robot_logs, record_every=every,
                       record_scans=scans, name=name,
                       source=str(Path(source).resolve()) if source else "", until=until,
                       ros_timeout=None if ros_timeout is None else float(ros_timeout),
                       primary=primary, isolation=isolation, sandbox=sandbox)


def _primary(value: Any, fail: Any) -> str:
    """``[battery] primary``: an outcome metric's name ("" for the default)."""
    outcomes = [name for name, metric in METRICS.items() if not metric.cost]
    if value != "" and (not isinstance(value, str) or value not in outcomes):
        raise fail(f"[battery] primary: expected one of {', '.join(outcomes)} (the metric the "
                   f"battery answers; costs such as wall_time are not outcomes), got {value!r}")
    return value


def _limited(check: Any, name: str, value: Any, fail: Any) -> None:
    """``check`` (a :mod:`mimics.world.limits` check: a number, not a bool or a text, within
    the limit) of ``value``, its error naming the file too."""
    try:
        check(name, value)
    except MimicsError as exc:
        raise fail(str(exc)) from None


def _is_number(value: Any) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool)


def _no_unknown(table: dict[str, Any], known: tuple[str, ...], where: str, fail: Any) -> None:
    for key in table:
        if key not in known:
            raise fail(f"{where}: unknown key {key!r} (expected one of: {', '.join(known)})")


def _seeds(value: Any, fail: Any) -> tuple[int, ...]:
    if isinstance(value, int) and not isinstance(value, bool):
        if not 1 <= value <= MAX_RUNS:
            raise fail(f"[battery] seeds: expected a count from 1 to {MAX_RUNS} or a list of "
                       f"seeds, got {value}")
        return tuple(range(1, value + 1))
    if isinstance(value, list) and len(value) > MAX_RUNS:
        raise fail(f"[battery] seeds: {len(value)} seeds, over the limit of {MAX_RUNS} runs")
    if (isinstance(value, list) and value
            and all(isinstance(s, int) and not isinstance(s, bool) and 0 <= s <= MAX_SEED
                    for s in value)):
        if len(set(value)) != len(value):
            raise fail(f"[battery] seeds: a seed is listed twice in {value}")
        return tuple(value)
    raise fail(f"[battery] seeds: expected a count >= 1 or a non-empty list of whole numbers "
               f"from 0 to {MAX_SEED}, got {value!r}")


def _scenarios(value: Any, base: Path, fail: Any) -> tuple[ScenarioEntry, ...]:
    if not isinstance(value, list) or not value or not all(isinstance(s, dict) for s in value):
        raise fail("missing [[scenarios]] tables (each with at least `name`)")
    entries: list[ScenarioEntry] = []
    for k, table in enumerate(value, start=1):
        where = f"[[scenarios]] #{k}"
        name = table.get("name")
        if not isinstance(name, str) or not name:
            raise fail(f"{where}: missing `name` (a built-in scenario or a .py/.toml path)")
        ref = resolve(name, base)
        params = {key: v for key, v in table.items() if key != "name"}
        for key, v in params.items():
            if isinstance(v, list) and not v:
                raise fail(f"{where} ({name}): {key}: an empty list sweeps nothing")
        entry = ScenarioEntry(ref, Path(ref).stem if is_path(ref) else ref, params)
        _check_scenario(entry, f"{where} ({name})", fail)
        if entry in entries:
            raise fail(f"{where}: the same scenario and parameters are listed twice")
        _no_shared_points(entry, entries, where, fail)
        entries.append(entry)
    return tuple(entries)


def _no_shared_points(entry: ScenarioEntry, earlier: list[ScenarioEntry], where: str,
                      fail: Any) -> None:
    """Refuse a table whose parameter points an earlier table of the same scenario has
    (``robots = 10`` after ``robots = [1, 10]``): those runs would run twice."""
    points = entry.points()
    for k, other in enumerate(earlier, start=1):
        if other.ref != entry.ref:
            continue
        shared = next((p for p in other.points() if p in points), None)
        if shared is not None:
            given = ", ".join(f"{key} = {value_text(v)}" for key, v in entry.params.items())
            before = ", ".join(f"{key} = {value_text(v)}" for key, v in other.params.items())
            point = ", ".join(f"{key} = {value_text(v)}" for key, v in shared.items())
            raise fail(f"{where}: {given or 'no parameters'} repeats runs of [[scenarios]] #{k} "
                       f"({before or 'no parameters'}): {point or 'the defaults'}; give each "
                       "point once")


def _check_scenario(entry: ScenarioEntry, where: str, fail: Any) -> None:
    """The scenario exists and takes these parameters (with values of the right kind)."""
    from mimics.catalog import load_scenario, scenario_parameters

    try:
        if entry.ref.endswith(".toml"):  # declarative: cheap to build, so build every point
            for point in entry.points():
                load_scenario(entry.ref, **point)
            return
        defaults = scenario_parameters(entry.ref)
    except MimicsError as exc:
        raise fail(f"{where}: {exc}") from None
    for key, value in entry.params.items():
        if key not in defaults:
            known = ", ".join(defaults) or "none"
            raise fail(f"{where}: scenario {entry.name!r} has no parameter {key!r} (expected "
                       f"one of: {known})")
        default = defaults[key]
        for v in value if isinstance(value, list) else [value]:
            if not _same_kind(v, default):
                raise fail(f"{where}: {key}: expected a value like the default {default!r}, got "
                           f"{v!r}")
            try:  # the counts every scenario shares, checked here rather than in each run
                if key == "robots":
                    check_whole(f"{key}", v, 1, MAX_ROBOTS)
                elif key == "seed":
                    check_whole(f"{key}", v, 0, MAX_SEED)
                elif key == "time_limit":
                    check_time(key, v)
            except MimicsError as exc:
                raise fail(f"{where}: {exc}") from None


def _same_kind(value: Any, default: Any) -> bool:
    if default is None:
        return True
    if isinstance(default, bool):
        return isinstance(value, bool)
    if isinstance(default, int):
        return isinstance(value, int) and not isinstance(value, bool)
    if isinstance(default, float):
        return _is_number(value)
    if isinstance(default, str):
        return isinstance(value, str)
    return True


# -- writing (``mimics battery new``) ------------------------------------------

def battery_toml(algorithms: list[str], scenarios: list[dict[str, Any]], *,
                 seeds: int | list[int] = 1, time: float | None = None,
                 timeout: float = DEFAULT_TIMEOUT, policy: str = "abort",
                 robot_logs: str = "off") -> str:
    """The text of a battery file (the form ``mimics battery new`` saves).

    Args:
        algorithms: names or paths, as they should appear in the file.
        scenarios: ``{"name": ..., param: value or [values]}`` tables.
        seeds: a count or a list of seeds.
        time: simulated seconds per run (None: the scenario's).
        timeout: wall-clock seconds per run.
        policy: ``"abort"`` or ``"deactivate"``.
        robot_logs: ``"off"``, ``"auto"`` or ``"on"``.
    """
    import tomli_w

    battery: dict[str, Any] = {"algorithms": list(algorithms), "seeds": seeds}
    if time is not None:
        battery["time"] = float(time)
    battery.update(timeout=timeout, policy=policy, robot_logs=robot_logs)
    return tomli_w.dumps({"battery": battery, "scenarios": scenarios})
