"""The fuzzer's second round on the command line: outputs that alias inputs, and every
command reached.

* Every command that reads a run folder, a battery folder or a map file and has an
  output option is given, as that output, a generated alias of what it reads (one
  of the records, through ``..``, the folder itself, one file for two outputs):
  it must exit 2 and leave every input byte for byte as it was.
* The Typer app is walked on its own (its registered commands and sub-apps, not
  the click tree the fuzzer walks), and every command found must be one the
  fuzzer calls, and reached by it: a new command the fuzzer never calls fails here.
"""

from __future__ import annotations

import tempfile
from pathlib import Path
from typing import Any

import pytest
import typer
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mimics.interfaces.cli import app
from tests.fuzzing import BATTERY_ALIASES, RUN_ALIASES, copy_tree, snapshot
from tests.interfaces.test_fuzz_cli import (
    COMMANDS,
    ONLY_BAD_VALUES,
    OUTPUT_OPTIONS,
    invoke,
    template,
)

__all__ = ["template"]  # the inputs fixture, shared with the first round's fuzzer

#: Argument names that are a folder or file the command reads, and the aliases of each.
READ_ARGUMENTS = {
    "run": [a.format(run="inputs/run", name="run") for a in RUN_ALIASES],
    "folder": [a.format(folder="inputs/battery_folder", name="battery_folder")
               for a in BATTERY_ALIASES],
    "directory": [a.format(folder="inputs/battery_folder", name="battery_folder")
                  for a in BATTERY_ALIASES],
    "file": ["inputs/maps/room.toml", "inputs/maps/../maps/room.toml"],
    "map": ["inputs/maps/room.toml"],
}
SOURCES = {"run": "inputs/run", "folder": "inputs/battery_folder",
           "directory": "inputs/battery_folder", "file": "inputs/maps/room.toml",
           "map": "inputs/maps/room.toml"}


def aliasing_commands() -> list[tuple[tuple[str, ...], Any, Any, list[Any]]]:
    """(path, command, the argument it reads, its output options) of every such command."""
    found = []
    for path, command in COMMANDS:
        if path in ONLY_BAD_VALUES:
            continue
        reads = [p for p in command.params
                 if p.param_type_name == "argument" and p.name in READ_ARGUMENTS]
        writes = [p for p in command.params
                  if p.param_type_name == "option" and p.name in OUTPUT_OPTIONS]
        if reads and writes:
            found.append((path, command, reads[0], writes))
    return found


ALIASING = aliasing_commands()


@pytest.mark.parametrize(("path", "command", "reads", "writes"), ALIASING,
                         ids=[" ".join(p) for p, *_ in ALIASING])
def test_an_output_aliasing_what_the_command_reads_is_refused_and_nothing_changes(
        path: tuple[str, ...], command: Any, reads: Any, writes: list[Any], template: Path,
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)

    @settings(max_examples=6, deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
    @given(data=st.data())
    def check(data: st.DataObject) -> None:
        alias = data.draw(st.sampled_from(READ_ARGUMENTS[reads.name]), label="alias")
        option = data.draw(st.sampled_from(writes), label="option")
        argv = [*path]
        for param in command.params:  # every argument ordinary, the one read fixed
            if param.param_type_name == "argument":
                argv.append(SOURCES[param.name] if param is reads else "line")
        argv += [option.opts[0], alias]
        others = [w for w in writes if w is not option]
        if others and data.draw(st.booleans(), label="two outputs, one file"):
            argv = [*argv[:-2], option.opts[0], "out.x", others[0].opts[0], "./out.x"]
        with tempfile.TemporaryDirectory() as tmp:
            work = Path(tmp)
            copy_tree(template, work / "inputs")
            monkeypatch.setenv("MIMICS_CONFIG_DIR", str(work / "config"))
            before = snapshot(work / "inputs")
            status, output = invoke(argv, work)
            assert status == 2, f"mimics {argv}: status {status}\n{output}"
            assert "Traceback" not in output
            assert snapshot(work / "inputs") == before, f"mimics {argv} changed its inputs"
            assert not (work / "out.x").exists()

    check()


def test_the_commands_that_alias_are_found() -> None:
    names = {" ".join(path) for path, *_ in ALIASING}
    assert {"export", "plot", "replay", "logs export", "battery report", "battery compare",
            "battery plot", "map import", "map show"} <= names


def typer_commands(typer_app: typer.Typer, prefix: tuple[str, ...] = ()) -> set[tuple[str, ...]]:
    """Every command registered on ``typer_app`` and its sub-apps, by name, as Typer names
    them (the registered name, else the function's, with dashes)."""
    found = set()
    for info in typer_app.registered_commands:
        name = info.name or info.callback.__name__.replace("_", "-")  # type: ignore[union-attr]
        found.add((*prefix, name))
    for group in typer_app.registered_groups:
        name = group.name or group.typer_instance.info.name  # type: ignore[union-attr]
        found |= typer_commands(group.typer_instance, (*prefix, name))  # type: ignore[arg-type]
    return found


def test_every_registered_command_is_called_and_reached_by_the_fuzzer(
        tmp_path: Path) -> None:
    registered = typer_commands(app)
    fuzzed = {path for path, _ in COMMANDS}
    missing = sorted(" ".join(p) for p in registered - fuzzed)
    assert not missing, f"commands the fuzzer never calls: {missing}"
    assert len(registered) >= 20
    # reached: the fuzzer's command line gets to the command's own parser (an option it
    # does not have is then its own "No such option", not the group's "No such command")
    for path in sorted(registered):
        status, output = invoke([*path, "--no-such-option"], tmp_path)
        assert status == 2 and "No such option" in output, (path, output)
