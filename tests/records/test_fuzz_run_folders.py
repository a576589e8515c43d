"""A fuzzer over run folders: summary.json, scenario.toml and the Parquet files damaged.

A finished run folder is copied, one of its files damaged (truncated, bytes
flipped, emptied, garbage, or for summary.json keys dropped and values of the
wrong type), and read back through :func:`mimics.load_run` and the commands
that read runs (``mimics report``, ``mimics logs export``). The property: the
run loads and reads, or one ``MimicsError`` line (status 2 from the command
line); never another exception, a traceback or another status; and the
folder's other files are still there.
"""

from __future__ import annotations

import contextlib
import io
import json
import shutil
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mimics.interfaces.cli import main
from mimics.records.run_folder import load_run
from mimics.world.errors import MimicsError
from tests.fuzzing import damaged_bytes, make_run_folder

FILES = ["summary.json", "scenario.toml", "trajectory.parquet", "events.parquet"]
JSON_VALUES = st.one_of(st.none(), st.booleans(), st.integers(-2**70, 2**70),
                        st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=5),
                        st.lists(st.integers(), max_size=2), st.just({}))


@pytest.fixture(scope="module")
def finished_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return make_run_folder(tmp_path_factory.mktemp("fuzz-runs") / "run")


@st.composite
def damaged_summary(draw: Any, text: str) -> bytes:
    """summary.json with keys dropped or given values of the wrong type."""
    data = json.loads(text)
    for key in draw(st.lists(st.sampled_from(sorted(data)), min_size=1, max_size=3, unique=True)):
        if draw(st.booleans()):
            del data[key]
        else:
            data[key] = draw(JSON_VALUES)
    return json.dumps(data).encode()  # NaN and Infinity as Python writes them


def read_everything(folder: Path) -> None:
    """What a user of a run reads: the summary, the scenario, the tables, a robot."""
    run = load_run(folder)
    _ = run.summary, run.complete
    _ = run.scenario, run.info
    _ = run.trajectory, run.events
    _ = run.robot(0)


def cli(argv: list[str]) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        status = main(argv)
    return status, out.getvalue()


@settings(max_examples=30, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(name=st.sampled_from(FILES), data=st.data())
def test_damaged_run_folders_load_or_fail_in_one_line(finished_run: Path, tmp_path_factory: Any,
                                                      name: str, data: st.DataObject) -> None:
    folder = tmp_path_factory.mktemp("damaged") / "run"
    shutil.copytree(finished_run, folder)
    original = (folder / name).read_bytes()
    damage = damaged_bytes(original)
    if name == "summary.json":
        damage = st.one_of(damage, damaged_summary(original.decode()))
    (folder / name).write_bytes(data.draw(damage, label=name))
    before = sorted(p.relative_to(folder) for p in folder.rglob("*"))
    try:
        read_everything(folder)
    except MimicsError as exc:
        assert "\n" not in str(exc)
    for command in (["report", str(folder)], ["logs", "export", str(folder), "--robot", "0",
                                              "--out", str(folder.parent / "logs")]):
        status, output = cli(command)
        assert status in (0, 2), f"mimics {command}: {status}\n{output}"
        assert "Traceback" not in output, output
    after = sorted(p.relative_to(folder) for p in folder.rglob("*"))
    assert set(before) <= set(after), "a command removed files from the run folder"
