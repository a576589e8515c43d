"""Bad input: not a run, truncated or corrupt files, bad options: one line naming the file."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
import typer
from typer.testing import CliRunner

import mimics
from mimics.algorithms import go_to_goal
from mimics.engine.simulation import Simulation
from mimics.interfaces.cli.records import logs_app, report_command
from mimics.records.recorder import RunRecorder
from mimics.records.robot_logs import read_robot_log
from mimics.records.runner import run_to_folder
from mimics.world.errors import MimicsError

from .helpers import head_on, record


@pytest.fixture(scope="module")
def good_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("good") / "run"
    record(head_on(), go_to_goal, folder)
    return folder


def cli() -> typer.Typer:
    app = typer.Typer()
    app.command("report")(report_command)
    app.add_typer(logs_app, name="logs")
    return app


def broken_copy(good: Path, tmp_path: Path, name: str, keep: float = 0.5) -> Path:
    """A copy of the run with file ``name`` cut to ``keep`` of its bytes."""
    copy = tmp_path / "copy"
    shutil.copytree(good, copy)
    data = (copy / name).read_bytes()
    (copy / name).write_bytes(data[:int(len(data) * keep)])
    return copy


def one_line_error(path: Path, *needles: str) -> None:
    with pytest.raises(MimicsError) as info:
        mimics.load_run(path)
    message = str(info.value)
    assert "\n" not in message
    for needle in needles:
        assert needle in message, message


def test_not_a_run_folder(tmp_path: Path) -> None:
    one_line_error(tmp_path / "missing", str(tmp_path / "missing"), "not a run folder",
                   "no such directory")
    (tmp_path / "file.txt").write_text("x")
    one_line_error(tmp_path / "file.txt", "not a run folder", "it is a file")
    (tmp_path / "empty").mkdir()
    one_line_error(tmp_path / "empty", "not a run folder", "summary.json")


@pytest.mark.parametrize("name", ["trajectory.parquet", "events.parquet"])
def test_truncated_parquet(good_run: Path, tmp_path: Path, name: str) -> None:
    copy = broken_copy(good_run, tmp_path, name)
    one_line_error(copy, str(copy / name), "truncated or corrupt")


def test_corrupt_summary_and_scenario(good_run: Path, tmp_path: Path) -> None:
    copy = broken_copy(good_run, tmp_path, "summary.json")
    one_line_error(copy, str(copy / "summary.json"), "not a readable summary")
    (copy / "summary.json").unlink()
    (copy / "scenario.toml").write_text("name = 'x'\nrobots = [\n")
    one_line_error(copy, str(copy / "scenario.toml"), "not valid TOML")


def test_missing_trajectory_of_a_finished_run(good_run: Path, tmp_path: Path) -> None:
    copy = tmp_path / "copy"
    shutil.copytree(good_run, copy)
    (copy / "trajectory.parquet").unlink()
    one_line_error(copy, str(copy / "trajectory.parquet"), "missing")


def test_cli_errors_are_one_line_with_status_2(good_run: Path, tmp_path: Path) -> None:
    runner = CliRunner()
    for args in (["report", str(tmp_path / "nope")], ["logs", "export", str(tmp_path / "nope")],
                 ["logs", "export", str(good_run), "--robot", "9"]):
        result = runner.invoke(cli(), args)
        assert result.exit_code == 2, (args, result.output)
        assert result.stderr.count("\n") == 1 and result.stderr.startswith("mimics: error: ")
    copy = broken_copy(good_run, tmp_path, "trajectory.parquet")
    result = runner.invoke(cli(), ["report", str(copy)])
    assert result.exit_code == 2 and "trajectory.parquet" in result.stderr


def test_bad_robot_index_and_log(good_run: Path, tmp_path: Path) -> None:
    run = mimics.load_run(good_run)
    for bad in (4, -1, True):
        with pytest.raises(MimicsError, match="no such robot"):
            run.robot(bad)  # type: ignore[arg-type]
    (tmp_path / "x.log").write_text("hello\n")
    with pytest.raises(MimicsError, match="not a per-robot log"):
        read_robot_log(tmp_path / "x.log")


def test_bad_recorder_options(tmp_path: Path) -> None:
    for options in ({"robot_logs": "maybe"}, {"every": 0}, {"flush_rows": 0},
                    {"flush_seconds": 0}):
        with pytest.raises(MimicsError):
            RunRecorder(tmp_path, **options)  # type: ignore[arg-type]
    sim = Simulation(head_on(), go_to_goal, seed=1)
    sim.run()
    with pytest.raises(MimicsError, match="already run"):
        run_to_folder(sim, tmp_path)


def test_an_unwritable_folder_is_one_line(tmp_path: Path) -> None:
    (tmp_path / "file.txt").write_text("x")
    sim = Simulation(head_on(), go_to_goal, seed=1)
    with pytest.raises(MimicsError, match="cannot write the run folder"):
        run_to_folder(sim, tmp_path / "file.txt" / "run")
