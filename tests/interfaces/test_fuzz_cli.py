"""A fuzzer over every command of the command line, found by walking the command tree.

Every leaf command of ``mimics`` (those other modules mount too: the walk runs
when the tests are collected) gets generated arguments and options: numbers at
the edges (huge, tiny, negative, zero, NaN, infinite, not numbers at all),
strings (empty, non-ASCII, long), and paths to valid, damaged and missing
inputs. The property, for every example:

* the exit status is 0, 1 or 2 (``mimics --help``), and nothing escapes ``main``;
* no "Traceback" is printed;
* nothing is written outside the example's working folder, and no file that
  was already there is lost or changed, unless the command was pointed at it.

Commands that serve until interrupted, or reach the network, are listed in
:data:`ONLY_BAD_VALUES`: they get at least one certainly bad value and must
fail fast with status 2. Every call runs under a time guard, so a new command
that serves forever fails this test (naming it) instead of hanging the suite.
"""

from __future__ import annotations

import contextlib
import io
import os
import tempfile
from pathlib import Path
from typing import Any

import pytest
import typer
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mimics.interfaces.cli import app, main
from tests.fuzzing import (
    BATTERY_TOML,
    ENORMOUS,
    SCENARIO_TOML,
    Hung,
    copy_tree,
    foreign_run_folder,
    make_run_folder,
    map_files,
    snapshot,
    time_guard,
)

#: Commands that serve until interrupted (a web server, a ROS node) or reach the network:
#: only certainly-bad values are given to them, and they must exit 2 at once. A command
#: missing from here that hangs fails the test by the time guard, naming itself.
ONLY_BAD_VALUES: dict[tuple[str, ...], str] = {
    ("ui",): "serves the browser interface until interrupted",
    ("ros",): "runs a ROS node until interrupted",
    ("ros2",): "joins the ROS 2 DDS graph (the network) until interrupted",
    ("data", "get"): "downloads from the internet",
}
GUARD_SECONDS = 60  # far above any example's time (a run of 60 robots takes about 2 s)
#: Options whose value is a path the command writes (files under it may change or go).
OUTPUT_OPTIONS = ("out", "output", "video", "gif", "csv", "parquet", "dest", "mcap", "bag",
                  "marks_csv")

#: Numbers: ordinary ones (drawn half the time, so that commands get past their first
#: check) and edge ones: negative, zero, tiny, huge, past 64 bits, NaN, infinite, not numbers.
INT_GOOD = ["1", "2", "3", "64", "200"]
INT_EDGE = ["-1", "0", "-9223372036854775809", "9223372036854775808",
            "340282366920938463463374607431768211456", "2147483648", "10000000", "1e3", "nan",
            "", "ü", "0x1F", "1_0", "abc"]
FLOAT_GOOD = ["0.25", "1", "2.5", "10", "0.3"]
FLOAT_EDGE = ["nan", "inf", "-inf", "1e999", "-1", "0", "-0.0", "5e-324", "1e-300", "1e15", "",
              "ü", "abc", "1,5", *ENORMOUS]  # ENORMOUS: finite, past every limit
CERTAINLY_BAD = {int: ["nan", "9223372036854775808", "ü"], float: ["nan", "inf", "1e999"]}
PATHS = ["inputs/run", "inputs/run_damaged", "inputs/run_foreign", "inputs/battery.toml",
         "inputs/bad_battery.toml", "inputs/battery_folder", "inputs/scenario.toml",
         "inputs/bad_scenario.py",
         "inputs/maps/room.txt", "inputs/maps/plan.svg", "inputs/maps/grid.png",
         "inputs/maps/ros.yaml", "inputs/garbage.bin", "inputs/empty.toml", "inputs/folder",
         "inputs", "nonexistent", "nonexistent.toml", "out/new", "out/new.png", "out/new.mp4",
         "out/new.gif", "out/new.txt", "out/new.csv", "", "ü-ñ-∞.toml", "-", "a" * 300,
         "line", "go_to_goal", "stage:cave", "/dev/null", "runs/../inputs/run",
         "inputs/run/summary.json", "inputs/run/trajectory.parquet",
         "inputs/battery_folder/battery.db", "inputs/run/../run/events.parquet"]
#: What a parameter of this name usually takes (a new command's parameters with other names
#: draw from everything).
HINTS: dict[str, list[str]] = {
    "scenario": ["inputs/scenario.toml", "line", "inputs/bad_scenario.py", "circle_swap"],
    "algorithm": ["go_to_goal", "go_to_goal_team", "inputs/raising_algorithm.py"],
    "run": ["inputs/run", "inputs/run_damaged", "inputs/run_foreign"],
    "folder": ["inputs/battery_folder"], "directory": ["inputs/battery_folder"],
    "battery": ["inputs/battery.toml", "inputs/bad_battery.toml"],
    "file": ["inputs/maps/room.txt", "inputs/maps/plan.svg", "inputs/maps/grid.png",
             "inputs/maps/grid.pgm", "inputs/maps/ros.yaml", "inputs/maps/room.json"],
    "map": ["inputs/maps/room.txt", "inputs/maps/room.toml", "inputs/maps/plan.svg"],
    "out": ["out/new", "out/new.png", "out/new.txt", "out/new.gif"],
    "output": ["out/battery.toml"], "video": ["out/new.mp4"], "gif": ["out/new.gif"],
    "csv": ["out/new.csv"], "parquet": ["out/new.parquet"], "mcap": ["out/new.mcap"],
    "bag": ["out/new.bag"],
    "policy": ["abort", "deactivate"], "robot_logs": ["off", "on", "auto"], "view": ["off"],
    "param": ["robots=2", "spacing=0", "spacing=-1", "distance=1e308", "x_offset=nan",
              "seed=-1", "robots=1e999", "robots=ü", "nope=1", "=", "time_limit=1e300",
              "robots=3", "dt=0"],
    "seeds": ["1", "1,5,9", "0", "-1", "99999999999999999999999", "1,,5", "1,", ",", " "],
    "state": ["error", "timeout", "crashed", "nope"],
}
WORDS = ["abort", "deactivate", "auto", "on", "off", "step", "1s", "stage", "error", "timeout",
         "robots=2", "spacing=0", "spacing=-1", "distance=1e308", "x_offset=nan", "seed=-1",
         "robots=1e999", "robots=ü", "nope=1", "=", "1,5,9", "30", "0", "-1", "tcp://"]


def leaf_commands() -> list[tuple[tuple[str, ...], Any]]:
    """Every command that runs something, with its path (``("battery", "run")``)."""
    found = []

    def walk(command: Any, path: tuple[str, ...]) -> None:
        subs = getattr(command, "commands", None)
        if subs:
            for name, sub in subs.items():
                walk(sub, (*path, name))
        else:
            found.append((path, command))

    walk(typer.main.get_command(app), ())
    return found


COMMANDS = leaf_commands()


CLICK_KINDS = {"integer": int, "float": float, "boolean": bool}


def kind(param: Any) -> type:
    """int, float, bool or str (of one value or of each of several), from the click
    parameter type Typer made of the annotation."""
    return CLICK_KINDS.get(getattr(param.type, "name", ""), str)


@st.composite
def value_for(draw: Any, param: Any, bad_only: bool = False) -> list[str]:
    """The command-line tokens of one parameter (option name included)."""
    base = kind(param)
    if base is bool:
        return [draw(st.sampled_from([*param.opts, *param.secondary_opts]))]
    if bad_only and base in (int, float):
        pools = [CERTAINLY_BAD[base]]
    elif base in (int, float):
        pools = [INT_GOOD, INT_EDGE] if base is int else [FLOAT_GOOD, FLOAT_EDGE]
    else:
        pools = [HINTS[param.name], PATHS + WORDS] if param.name in HINTS else [PATHS + WORDS]
    pool = draw(st.sampled_from(pools))
    values = [draw(st.sampled_from(pool)) for _ in range(max(1, param.nargs))]
    if param.param_type_name == "argument":
        return values
    repeat = draw(st.integers(1, 2)) if param.multiple else 1
    return [token for _ in range(repeat) for token in (param.opts[0], *values)]


@st.composite
def command_line(draw: Any, path: tuple[str, ...], command: Any, bad_only: bool) -> list[str]:
    """Arguments in order, a random subset of options, sometimes an unknown option."""
    tokens: list[str] = list(path)
    options = [p for p in command.params if p.param_type_name == "option"]
    for param in command.params:
        if param.param_type_name == "argument" and draw(st.integers(0, 19)) > 0:
            tokens += draw(value_for(param))
    chosen = draw(st.lists(st.sampled_from(options), unique_by=lambda p: p.name,
                           max_size=min(4, len(options)))) if options else []
    for param in chosen:
        tokens += draw(value_for(param))
    if bad_only:  # a value no command may accept: it must fail before doing anything
        numeric = [p for p in options if kind(p) in (int, float)]
        if numeric:
            tokens += draw(value_for(draw(st.sampled_from(numeric)), bad_only=True))
        else:
            tokens.append("--no-such-option")
    elif draw(st.integers(0, 19)) == 0:
        tokens.append("--no-such-option")
    return tokens


@pytest.fixture(scope="module")
def template(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The inputs every example starts from (copied fresh for each)."""
    from mimics.batteries.spec import load_battery
    from mimics.batteries.store import BatteryStore

    root = tmp_path_factory.mktemp("fuzz-cli") / "inputs"
    root.mkdir()
    run = make_run_folder(root / "run")
    damaged = copy_tree(run, root / "run_damaged")
    text = (damaged / "summary.json").read_text()
    (damaged / "summary.json").write_text(text[: len(text) // 2])
    (damaged / "trajectory.parquet").write_bytes(b"PAR1" + os.urandom(64))
    foreign_run_folder(run, root / "run_foreign")
    (root / "battery.toml").write_text(BATTERY_TOML)
    (root / "bad_battery.toml").write_text("[battery]\nalgorithms = [1e999]\nseeds = -3\n")
    BatteryStore.create(root / "battery_folder", load_battery(root / "battery.toml")).close()
    (root / "scenario.toml").write_text(SCENARIO_TOML)
    (root / "bad_scenario.py").write_text("def scenario(robots=3):\n    return 1 / 0\n")
    (root / "raising_algorithm.py").write_text("def step(robot):\n    raise RuntimeError('boom')\n")
    (root / "garbage.bin").write_bytes(bytes(range(256)) * 4)
    (root / "empty.toml").write_text("")
    (root / "folder").mkdir()
    map_files(root / "maps")
    return root


def targets(argv: list[str], command: Any) -> tuple[list[Path], list[Path]]:
    """Paths the command was given: as outputs, and all of them."""
    outputs, named = [], []
    flags = {opt: p.name for p in command.params for opt in p.opts}
    for k, token in enumerate(argv):
        if token and not token.startswith("-"):
            named.append(Path(token))
            if k and flags.get(argv[k - 1]) in OUTPUT_OPTIONS:
                outputs.append(Path(token))
    return outputs, named


def under(path: str, roots: list[Path], work: Path) -> bool:
    full = (work / "inputs" / path).resolve()
    return any(full == (work / r).resolve() or (work / r).resolve() in full.parents
               for r in roots if str(r))


def invoke(argv: list[str], work: Path) -> tuple[int, str]:
    """``mimics ARGV`` in ``work``, under the time guard; status and all output."""
    out = io.StringIO()
    here = os.getcwd()
    os.chdir(work)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out), \
                time_guard(GUARD_SECONDS, f"mimics {' '.join(argv)!r} (a command that serves "
                                          "until interrupted belongs in ONLY_BAD_VALUES)"):
            status = main(argv)
    finally:
        os.chdir(here)
    return status, out.getvalue()


#: Examples per command; commands that start worker processes or draw several figures
#: (seconds a call) get fewer, to keep the suite's time.
EXAMPLES = 12
FEWER_EXAMPLES = {("battery", "run"): 5, ("battery", "resume"): 5,
                  ("battery", "rerun-failed"): 5, ("battery", "plot"): 5}


@pytest.mark.parametrize(("path", "command"), COMMANDS,
                         ids=[" ".join(path) for path, _ in COMMANDS])
def test_every_command_exits_0_1_or_2_without_traceback_or_stray_writes(
        path: tuple[str, ...], command: Any, template: Path,
        monkeypatch: pytest.MonkeyPatch) -> None:
    bad_only = path in ONLY_BAD_VALUES
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)

    @settings(max_examples=FEWER_EXAMPLES.get(path, EXAMPLES), deadline=None,
              suppress_health_check=[HealthCheck.too_slow])
    @given(argv=command_line(path, command, bad_only))
    def check(argv: list[str]) -> None:
        with tempfile.TemporaryDirectory() as tmp:
            root = Path(tmp)
            work, outside = root / "work", root / "outside"
            copy_tree(template, work / "inputs")
            outside.mkdir()
            (outside / "sentinel.txt").write_text("must stay as it is")
            monkeypatch.setenv("MIMICS_CONFIG_DIR", str(work / "config"))
            before, outside_before = snapshot(work / "inputs"), snapshot(outside)
            try:
                status, output = invoke(argv, work)
            except Hung as exc:
                pytest.fail(str(exc))
            expected = {2} if bad_only else {0, 1, 2}
            assert status in expected, f"mimics {argv}: status {status}\n{output}"
            assert "Traceback" not in output, f"mimics {argv}:\n{output}"
            assert snapshot(outside) == outside_before, f"mimics {argv} wrote outside its folder"
            outputs, named = targets(argv, command)
            after = snapshot(work / "inputs")
            for name, digest in before.items():
                if under(name, outputs, work):
                    continue  # the command was told to write there
                assert name in after, f"mimics {argv} lost inputs/{name}"
                if not under(name, named, work):
                    assert after[name] == digest, f"mimics {argv} changed inputs/{name}"

    check()


def test_the_walk_finds_every_command_group() -> None:
    names = {" ".join(path) for path, _ in COMMANDS}
    assert {"run", "report", "battery run", "map import", "logs export", "list scenarios"} <= names
    assert all(command.params is not None for _, command in COMMANDS)


#: Values every parameter gets once, deterministically (the random examples above may miss
#: a rare one): empty, too long for a file name, not UTF-8, a device, a dash, non-ASCII.
EDGE_TEXT = ["", "a" * 300, "bad\udcffname", "/dev/null", "-", "ü-ñ-∞"]
EDGE_NUMBERS = {int: ["nan", "-1", "0", "9223372036854775808", "2147483648"],
                float: ["nan", "inf", "1e999", "-1", "0", "5e-324", "1e300", "1e308"]}


def edge_lines(path: tuple[str, ...], command: Any) -> list[list[str]]:
    """One command line per (parameter, edge value), the other arguments ordinary."""
    arguments = [p for p in command.params if p.param_type_name == "argument"]
    ordinary = {p.name: HINTS.get(p.name, ["nonexistent"])[0] for p in arguments}
    lines = []
    for param in command.params:
        base = kind(param)
        if base is bool:
            continue
        values = EDGE_NUMBERS[base] if base in (int, float) else EDGE_TEXT
        for value in values:
            tokens = [value] * max(1, param.nargs)
            if param.param_type_name == "argument":
                args = [tokens[0] if p is param else ordinary[p.name] for p in arguments]
                lines.append([*path, *args])
            else:
                lines.append([*path, *(ordinary[p.name] for p in arguments), param.opts[0],
                              *tokens])
    return lines


SWEPT = [(path, command) for path, command in COMMANDS if path not in ONLY_BAD_VALUES]


@pytest.mark.parametrize(("path", "command"), SWEPT, ids=[" ".join(p) for p, _ in SWEPT])
def test_every_parameter_takes_every_edge_value_without_traceback(
        path: tuple[str, ...], command: Any, template: Path, tmp_path: Path,
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.setenv("MIMICS_CONFIG_DIR", str(tmp_path / "config"))
    work = tmp_path / "work"
    copy_tree(template, work / "inputs")
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "sentinel.txt").write_text("must stay as it is")
    lines = edge_lines(path, command)
    assert lines or not command.params
    for argv in lines:
        try:
            status, output = invoke(argv, work)
        except Hung as exc:
            pytest.fail(str(exc))
        assert status in (0, 1, 2), f"mimics {argv}: status {status}\n{output}"
        assert "Traceback" not in output, f"mimics {argv}:\n{output}"
    assert snapshot(outside) == {"sentinel.txt": snapshot(outside)["sentinel.txt"]}
    assert (outside / "sentinel.txt").read_text() == "must stay as it is"


def test_the_time_guard_stops_a_command_that_would_serve_forever() -> None:
    import time

    with pytest.raises(Hung, match="still running after 1 s"), time_guard(1, "a server"):
        time.sleep(5)
