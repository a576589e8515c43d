"""The run folder of the paper's line scenario: every file, its schema, and logs that parse
back into the trajectory's values."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq
import pytest
import typer
from typer.testing import CliRunner

import mimics
from mimics.algorithms import go_to_goal
from mimics.catalog import load_scenario
from mimics.engine.simulation import Simulation
from mimics.engine.state import Status
from mimics.interfaces.cli.records import logs_app, report_command
from mimics.records import recorder as recorder_module
from mimics.records.events import EVENTS_SCHEMA
from mimics.records.robot_logs import (
    LOG_COLUMNS,
    LOG_UNITS,
    SOURCE_COLUMNS,
    log_uuid,
    read_robot_log,
)
from mimics.records.runner import run_to_folder
from mimics.records.trajectory import TRAJECTORY_SCHEMA
from mimics.scenarios.line import scenario as line

from .helpers import head_on, record

ROBOTS = 10


class Capture:
    """Copies the engine's state after every step, to compare with what was written."""

    def __init__(self) -> None:
        self.rows: list[dict[str, Any]] = []

    def _take(self, sim: Simulation) -> None:
        s = sim.state
        self.rows.append({"step": s.step, "pose": s.pose.copy(), "velocity": s.velocity.copy(),
                          "measured": s.measured_pose.copy(), "reference": s.reference.copy(),
                          "status": s.status.copy(), "user_time": s.user_time.copy()})

    def on_start(self, sim: Simulation) -> None:
        self._take(sim)

    def on_step(self, sim: Simulation) -> None:
        self._take(sim)


@pytest.fixture(scope="module")
def line_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Capture]:
    folder = tmp_path_factory.mktemp("runs") / "line-go_to_goal-s1"
    capture = Capture()
    sim = Simulation(load_scenario("line", robots=ROBOTS, random_yaw=False), go_to_goal, seed=1,
                     observers=[capture], algorithm_name="go_to_goal")
    run_to_folder(sim, folder)
    return folder, capture


def cli() -> typer.Typer:
    app = typer.Typer()
    app.command("report")(report_command)
    app.add_typer(logs_app, name="logs")
    return app


def test_the_line_run_leaves_every_file(line_run: tuple[Path, Capture]) -> None:
    folder, _ = line_run
    names = sorted(p.name for p in folder.iterdir())
    assert names == ["events.parquet", "robots", "scenario.toml", "summary.json", "summary.txt",
                     "trajectory.parquet"]
    logs = sorted(p.name for p in (folder / "robots").iterdir())
    assert logs == [f"robot_{i:04d}.log" for i in range(ROBOTS)]
    assert not list(folder.rglob("*.tmp"))


def test_trajectory_is_the_engine_state_at_every_step(line_run: tuple[Path, Capture]) -> None:
    folder, capture = line_run
    table = pq.read_table(folder / "trajectory.parquet")
    assert table.schema.equals(TRAJECTORY_SCHEMA)
    frame = table.to_pandas()
    assert len(frame) == ROBOTS * len(capture.rows)  # all arrive at the same, last, step
    for taken in capture.rows:
        rows = frame[frame["step"] == taken["step"]]
        assert rows["robot"].tolist() == list(range(ROBOTS))
        assert np.all(rows["time"] == round(taken["step"] * 0.1, 9))
        np.testing.assert_array_equal(rows[["x", "y", "theta"]].to_numpy(), taken["pose"])
        np.testing.assert_array_equal(rows[["v", "w"]].to_numpy(), taken["velocity"])
        np.testing.assert_array_equal(rows[["x_meas", "y_meas", "theta_meas"]].to_numpy(),
                                      taken["measured"])
        np.testing.assert_array_equal(rows[["v_ref", "heading_ref"]].to_numpy(),
                                      taken["reference"])
        np.testing.assert_array_equal(rows["status"].to_numpy(), taken["status"])
        np.testing.assert_array_equal(rows["user_time"].to_numpy(),
                                      taken["user_time"].astype(np.float32))
    last = frame[frame["step"] == frame["step"].max()]
    assert set(last["status"]) == {Status.REACHED_GOAL}


def test_summary_json_extends_the_engine_summary(line_run: tuple[Path, Capture]) -> None:
    folder, capture = line_run
    summary = json.loads((folder / "summary.json").read_text())
    engine_keys = {"status", "scenario", "algorithm", "seed", "robots", "sim_time", "wall_time",
                   "reached_goal", "collisions", "robot_collisions", "wall_collisions",
                   "escaped", "deadlocks", "livelocks", "exceptions", "user_code_time",
                   "time_to_goal", "path_length", "path_efficiency"}
    assert engine_keys <= set(summary)
    assert summary["status"] == "completed" and summary["reached_goal"] == ROBOTS
    assert summary["deadlock_episodes"] == 0 and summary["livelock_episodes"] == 0
    assert summary["mimics_version"] == recorder_module.mimics_version()
    assert summary["records"]["trajectory_rows"] == ROBOTS * len(capture.rows)
    assert summary["records"]["robot_logs"] is True
    assert set(summary["user_code_time"]) == {"calls", "mean", "p95", "max"}
    text = (folder / "summary.txt").read_text()
    assert text.startswith("line / go_to_goal / seed 1\n")
    assert "reached goal" in text and "(robot-robot 0, robot-wall 0)" in text


def test_each_robot_log_parses_back_into_the_trajectory(line_run: tuple[Path, Capture]
                                                        ) -> None:
    folder, _ = line_run
    run = mimics.load_run(folder)
    summary = run.summary
    for i in range(ROBOTS):
        log = read_robot_log(folder / "robots" / f"robot_{i:04d}.log")
        assert log.header == {
            "scenario": "line", "algorithm": "go_to_goal", "creation time": summary["created"],
            "log uuid": log_uuid(summary["run_uuid"], i), "robot id": str(i),
            "type": "Pioneer3AT", "vehicle width": "0.5", "vehicle length": "0.7", "seed": "1"}
        assert log.columns == LOG_COLUMNS and log.units == LOG_UNITS
        rows = run.robot(i)
        for log_column, source in zip(LOG_COLUMNS, SOURCE_COLUMNS, strict=False):
            np.testing.assert_array_equal(log.table[log_column].to_numpy(),
                                          rows[source].to_numpy(), err_msg=log_column)
        assert log.deactivation == "Reached goal"
        assert log.table["sys_msg"].iloc[-1] == "Reached goal"
        assert set(log.table["user_msg"]) == {""}


def test_the_log_has_the_papers_layout(line_run: tuple[Path, Capture]) -> None:
    folder, _ = line_run
    lines = (folder / "robots" / "robot_0003.log").read_text().split("\n")
    assert lines[4] == "robot id = 3" and lines[9] == ""
    assert lines[10] == "time;x_gt;y_gt;phi_gt;v_gt;w_gt;x;y;phi;v_ref;phi_ref;user_msg;sys_msg"
    assert lines[11] == "[s];[m];[m];[rad];[m/s];[rad/s];[m];[m];[rad];[m/s];[rad];[];[]"
    assert lines[12] == "0;0;4;0;0;0;0;4;0;0;0;;"
    assert lines[-3:] == ["", "Deactivation: Reached goal", ""]


def test_each_log_byte_for_byte(line_run: tuple[Path, Capture]) -> None:
    """Each log file rebuilt row by row from trajectory.parquet, each number cast to text
    on its own by Arrow (the logs' number form), against the file's bytes: the writer's
    runs, groups, threads and pieces change nothing."""
    import pyarrow as pa

    folder, _ = line_run
    table = pq.read_table(folder / "trajectory.parquet").to_pylist()
    summary = json.loads((folder / "summary.json").read_text())
    for i in range(ROBOTS):
        rows = [row for row in table if row["robot"] == i]
        lines = ["scenario = line", "algorithm = go_to_goal",
                 f"creation time = {summary['created']}",
                 f"log uuid = {log_uuid(summary['run_uuid'], i)}", f"robot id = {i}",
                 "type = Pioneer3AT", "vehicle width = 0.5", "vehicle length = 0.7", "seed = 1",
                 "", ";".join(LOG_COLUMNS), ";".join(LOG_UNITS)]
        for number, row in enumerate(rows):
            texts = [pa.array([float(row[name])]).cast(pa.string())[0].as_py()
                     for name in SOURCE_COLUMNS]
            ending = ";Reached goal" if number == len(rows) - 1 else ";"
            lines.append(";".join(texts) + ";" + ending)
        lines += ["", "Deactivation: Reached goal", ""]
        path = folder / "robots" / f"robot_{i:04d}.log"
        assert path.read_bytes() == "\n".join(lines).encode(), path.name


def test_logs_export_writes_the_same_files(line_run: tuple[Path, Capture],
                                           tmp_path: Path) -> None:
    folder, _ = line_run
    copy = tmp_path / "copy"
    shutil.copytree(folder, copy)
    shutil.rmtree(copy / "robots")
    result = CliRunner().invoke(cli(), ["logs", "export", str(copy)])
    assert result.exit_code == 0, result.output
    assert f"wrote {ROBOTS} robot logs" in result.output
    for original in sorted((folder / "robots").iterdir()):
        assert (copy / "robots" / original.name).read_bytes() == original.read_bytes()
    result = CliRunner().invoke(cli(), ["logs", "export", str(copy), "--robot", "2", "--out",
                                        str(tmp_path / "two")])
    assert result.exit_code == 0
    assert [p.name for p in (tmp_path / "two").iterdir()] == ["robot_0002.log"]


def test_load_run_gives_back_everything(line_run: tuple[Path, Capture]) -> None:
    folder, capture = line_run
    run = mimics.load_run(folder)
    assert run.complete and run.summary["robots"] == ROBOTS
    original = load_scenario("line", robots=ROBOTS, random_yaw=False)
    np.testing.assert_array_equal(run.scenario.stages, original.stages)
    np.testing.assert_array_equal(run.scenario.goals, original.goals)
    assert run.scenario.types == original.types and run.scenario.map == original.map
    assert run.scenario.settings == original.settings
    assert run.scenario.parameters["robots"] == ROBOTS
    assert run.info["seed"] == 1 and run.info["algorithm"] == "go_to_goal"
    assert list(run.trajectory.columns) == TRAJECTORY_SCHEMA.names
    assert list(run.events.columns) == EVENTS_SCHEMA.names
    assert list(run.events["kind"]) == ["reached_goal"] * ROBOTS
    arrow = run.read_trajectory(columns=["step", "x"], robots=[1, 2], arrow=True)
    assert arrow.column_names == ["step", "x"] and arrow.num_rows == 2 * len(capture.rows)
    assert run.robot(4)["step"].tolist() == list(range(len(capture.rows)))
    assert run.log_path(4) == folder / "robots" / "robot_0004.log"
    assert "line / go_to_goal / seed 1" in repr(run)


def test_a_replay_reads_the_run_folder(line_run: tuple[Path, Capture]) -> None:
    from mimics.interfaces.replay import replay_data

    folder, capture = line_run
    data = replay_data(mimics.load_run(folder))
    assert data.n == ROBOTS and len(data.times) == len(capture.rows)
    assert math.isclose(data.duration, (len(capture.rows) - 1) * 0.1)


def test_report_prints_the_summary(line_run: tuple[Path, Capture]) -> None:
    folder, _ = line_run
    result = CliRunner().invoke(cli(), ["report", str(folder)])
    assert result.exit_code == 0, result.output
    assert "line / go_to_goal / seed 1" in result.output
    assert "reached goal" in result.output and "completed" in result.output


def test_robot_logs_auto_on_off(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(recorder_module, "AUTO_ROBOT_LOGS", 3)
    for robots, option, expected in ((3, "auto", True), (4, "auto", False), (2, "off", False),
                                     (4, "on", True)):
        folder = tmp_path / f"{robots}-{option}"
        run_to_folder(Simulation(line(robots=robots), go_to_goal, seed=1, time_limit=1.0),
                      folder, robot_logs=option)
        assert (folder / "robots").exists() is expected
        assert json.loads((folder / "summary.json").read_text())["records"]["robot_logs"] \
            is expected


def test_a_new_run_replaces_the_old_records(tmp_path: Path) -> None:
    record(head_on(), go_to_goal, tmp_path, seed=1)
    record(head_on(), go_to_goal, tmp_path, seed=2, robot_logs="off")
    run = mimics.load_run(tmp_path)
    assert run.summary["seed"] == 2 and run.info["seed"] == 2
    assert not (tmp_path / "robots").exists()


def test_every_records_deactivations_and_the_last_step(tmp_path: Path) -> None:
    record(head_on(), go_to_goal, tmp_path, every=5)
    run = mimics.load_run(tmp_path)
    steps = {i: run.robot(i)["step"].tolist() for i in range(4)}
    deactivated = {e.robot: e.step for e in run.events.itertuples()}
    for i in range(4):
        full = [k for k in range(0, deactivated[i] + 1, 5)]
        assert steps[i] == sorted(set(full) | {deactivated[i]})
        assert run.robot(i)["status"].iloc[-1] != Status.ACTIVE
    assert run.summary["records"]["every"] == 5
    assert run.summary["records"]["recorded_steps"] == run.trajectory["step"].nunique()
