"""Streaming: bounded buffers, parts merged into one file, and what a killed run leaves."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
import typer
from typer.testing import CliRunner

import mimics
from mimics.algorithms import go_to_goal
from mimics.engine.simulation import Simulation
from mimics.engine.state import Status
from mimics.interfaces.cli.records import logs_app, report_command
from mimics.records import recorder as recorder_module
from mimics.records.recorder import RunRecorder
from mimics.records.robot_logs import read_robot_log
from mimics.records.runner import run_to_folder

from .helpers import circle, head_on, record

REPO = Path(mimics.records.__file__).resolve().parents[2]


def without_timing(frame: pd.DataFrame) -> pd.DataFrame:
    return frame.drop(columns=["user_time"])


def test_parts_merge_into_the_same_table(tmp_path: Path) -> None:
    record(head_on(), circle, tmp_path / "one", robot_logs="on")
    record(head_on(), circle, tmp_path / "many", flush_rows=7, robot_logs="on")
    one, many = mimics.load_run(tmp_path / "one"), mimics.load_run(tmp_path / "many")
    pd.testing.assert_frame_equal(without_timing(one.trajectory), without_timing(many.trajectory))
    pd.testing.assert_frame_equal(one.events, many.events)
    assert not (tmp_path / "many" / "trajectory.parts").exists()
    for i in range(4):
        a = read_robot_log(tmp_path / "one" / "robots" / f"robot_{i:04d}.log")
        b = read_robot_log(tmp_path / "many" / "robots" / f"robot_{i:04d}.log")
        pd.testing.assert_frame_equal(a.table, b.table)


def test_logs_of_many_parts_are_the_same_from_the_merged_tables_or_read_back(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    given: list[bool] = []  # whether each run's logs were made from tables in memory
    write = recorder_module.write_robot_logs

    def spy(*args: Any, **kwargs: Any) -> Any:
        given.append(kwargs.get("trajectory") is not None)
        return write(*args, **kwargs)

    monkeypatch.setattr(recorder_module, "write_robot_logs", spy)
    record(head_on(), circle, tmp_path / "kept", flush_rows=7, robot_logs="on")
    monkeypatch.setattr(recorder_module, "KEEP_ROWS", 0)  # too many rows: read them back
    record(head_on(), circle, tmp_path / "read", flush_rows=7, robot_logs="on")
    assert given == [True, False]
    kept = sorted((tmp_path / "kept" / "robots").iterdir())
    read = sorted((tmp_path / "read" / "robots").iterdir())
    assert [p.name for p in kept] == [p.name for p in read]
    for ours, theirs in zip(kept, read, strict=True):
        # the same bytes below the header (whose creation time and uuid are each run's)
        body = ours.read_bytes().partition(b"\n\n")[2]
        assert body.count(b"\n") > 5
        assert body == theirs.read_bytes().partition(b"\n\n")[2]


class BufferWatch:
    """Observer placed after the recorder: the most rows it ever held."""

    def __init__(self, recorder: RunRecorder) -> None:
        self.recorder = recorder
        self.most = 0

    def on_step(self, sim: Simulation) -> None:
        self.most = max(self.most, self.recorder.buffered_rows)


def test_memory_is_bounded_by_the_flush_size(tmp_path: Path) -> None:
    recorder = RunRecorder(tmp_path, flush_rows=40, robot_logs="off")
    watch = BufferWatch(recorder)
    from mimics.scenarios.line import scenario

    sim = Simulation(scenario(robots=6, random_yaw=False), go_to_goal, seed=1,
                     observers=[recorder, watch])  # facing their goals: no robot stops early
    sim.run()
    assert 0 < watch.most < 40
    assert len(mimics.load_run(tmp_path).trajectory) == 6 * (sim.state.step + 1)


def test_a_run_that_raises_keeps_what_it_recorded(tmp_path: Path) -> None:
    class Crash:
        def on_step(self, sim: Simulation) -> None:
            if sim.state.step == 12:
                raise KeyboardInterrupt

    sim = Simulation(head_on(), go_to_goal, seed=1, observers=[Crash()])
    with pytest.raises(KeyboardInterrupt):
        run_to_folder(sim, tmp_path)
    run = mimics.load_run(tmp_path)
    assert not run.complete and run.summary["status"] == "incomplete"
    assert run.trajectory["step"].max() == 11  # the crash came before the recorder at step 12
    assert run.read_events(kinds=["reached_goal"])["robot"].tolist() == [3]


KILLED_RUN = textwrap.dedent("""
    import sys, time
    from mimics.engine.simulation import Simulation
    from mimics.records.runner import run_to_folder
    from mimics.scenarios.line import scenario

    def slow(robot):
        time.sleep(0.002)
        robot.log("alive")
        return robot.type.max_speed, 0.0

    sim = Simulation(scenario(robots=5, distance=500.0), slow, seed=1, time_limit=300.0,
                     algorithm_name="slow")
    run_to_folder(sim, sys.argv[1], flush_rows=25)
""")


def cli() -> typer.Typer:
    app = typer.Typer()
    app.command("report")(report_command)
    app.add_typer(logs_app, name="logs")
    return app


def test_a_killed_run_leaves_readable_records(tmp_path: Path) -> None:
    folder = tmp_path / "killed"
    script = tmp_path / "run.py"
    script.write_text(KILLED_RUN)
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    process = subprocess.Popen([sys.executable, str(script), str(folder)], env=env)
    parts = folder / "trajectory.parts"
    deadline = time.monotonic() + 60
    try:
        while len(list(parts.glob("part-*.parquet"))) < 4:
            assert process.poll() is None, "the run ended before it could be killed"
            assert time.monotonic() < deadline, "no parts written in 60 s"
            time.sleep(0.02)
    finally:
        process.send_signal(signal.SIGKILL)
        process.wait()
    assert not (folder / "summary.json").exists() and not (folder / "trajectory.parquet").exists()
    run = mimics.load_run(folder)
    assert not run.complete and run.summary["status"] == "incomplete"
    assert run.summary["algorithm"] == "slow" and run.summary["robots"] == 5
    frame = run.trajectory
    steps = np.unique(frame["step"])
    assert steps[0] == 0 and np.array_equal(steps, np.arange(len(steps))) and len(steps) >= 20
    assert len(frame) == 5 * len(steps)
    assert set(frame["status"]) == {Status.ACTIVE}
    messages = run.read_events(kinds=["user_message"])
    assert set(messages["detail"]) == {"alive"}
    result = CliRunner().invoke(cli(), ["logs", "export", str(folder), "--robot", "0"])
    assert result.exit_code == 0, result.output
    log = read_robot_log(folder / "robots" / "robot_0000.log")
    np.testing.assert_array_equal(log.table["x_gt"], run.robot(0)["x"])
    assert log.deactivation == "None (active when the run ended)"
    report = CliRunner().invoke(cli(), ["report", str(folder)])
    assert report.exit_code == 0 and "incomplete" in report.output
    assert "did not finish" in report.output
    info = json.loads(json.dumps(run.info))
    assert info["algorithm"] == "slow" and info["seed"] == 1
