"""A run edited live through SimulationStepper.edit is recorded (events.parquet rows of
kind ``edit``, ``[[edits]]`` in scenario.toml), and ``mimics run RUN/scenario.toml
ALGORITHM --seed S`` runs it again bit for bit: the same trajectory digest."""

from __future__ import annotations

import json
import math
import time
import tomllib
from pathlib import Path

from typer.testing import CliRunner

import mimics
from mimics.interfaces.cli import program as cli
from mimics.interfaces.stepper import SimulationStepper
from mimics.records.memory import MemoryRecorder, MemoryRun, save_run
from mimics.records.recorder import RunRecorder
from mimics.records.runner import prepare
from tests.interfaces.edited_world import line_in_the_walled_room

SCENARIO = line_in_the_walled_room(4, 1.0, 8.0)


def live_edited_run(tmp_path: Path) -> Path:
    """Record a run edited at steps 0, 6 and 15 while paused and once while playing."""
    source = tmp_path / "edited.toml"
    source.write_text(SCENARIO)
    folder = tmp_path / "live"
    sim = prepare(source, "go_to_goal", seed=4)
    sim.observers.append(RunRecorder(folder, robot_logs="off"))
    stepper = SimulationStepper(sim, lambda s: None, speed=math.inf)
    first = stepper.edit({"kind": "set_goal", "robot": 0, "x": 10.0, "y": -2.0})
    assert (first["step"], first["time"]) == (0, 0.0)
    for _ in range(6):
        stepper.step()
    assert stepper.wait_paused()
    moved = stepper.edit({"kind": "move_robot", "robot": 2, "x": 1.0, "y": 5.0, "yaw": 0.5})
    assert moved["step"] == 6 and moved["detail"] == "move robot 2 to (1, 5, yaw 0.5)"
    stepper.edit({"kind": "add_wall", "rectangle": [3.0, 0.5, 3.5, 1.5]})
    for _ in range(9):
        stepper.step()
    assert stepper.wait_paused()
    removed = stepper.edit({"kind": "remove_wall", "at": [6.1, 0.0]})
    assert removed["wall"] == 0 and removed["step"] == 15
    stepper.set_speed(5.0)  # playing, paced (8 s of run: 1.6 s at least)
    stepper.play()
    deadline = time.monotonic() + 120
    while sim.state.step < 20:  # the next edit lands between two steps of the playing run
        assert stepper.state == "playing" and time.monotonic() < deadline
        time.sleep(0.01)
    late = stepper.edit({"kind": "remove_robot", "robot": 3})
    assert late["step"] >= 20
    assert stepper.wait_ended(timeout=120)
    return folder


def test_a_live_edited_run_is_recorded_and_re_runs_bit_for_bit(tmp_path, monkeypatch):
    folder = live_edited_run(tmp_path)
    run = mimics.load_run(folder)
    assert run.summary["edits"] == 5 and run.summary["removed"] == 1
    rows = run.events[run.events.kind == "edit"]
    assert rows.robot.tolist() == [0, 2, -1, -1, 3]
    assert rows.step.tolist()[:4] == [0, 6, 6, 15]
    assert rows.time.tolist()[:4] == [0.0, 0.6, 0.6, 1.5]
    assert rows.detail.tolist()[3] == "remove wall 0"
    recorded = tomllib.loads((folder / "scenario.toml").read_text())
    assert [(e["step"], e["kind"]) for e in recorded["edits"]] == [
        (0, "set_goal"), (6, "move_robot"), (6, "add_wall"), (15, "remove_wall"),
        (rows.step.tolist()[4], "remove_robot")]
    monkeypatch.chdir(tmp_path)
    again = CliRunner().invoke(cli.app, ["run", str(folder / "scenario.toml"), "go_to_goal",
                                         "--seed", "4", "--out", "again"])
    assert again.exit_code == 0, again.output
    summary = json.loads((tmp_path / "again" / "summary.json").read_text())
    assert summary["trajectory_digest"] == run.summary["trajectory_digest"]
    assert summary["steps"] == run.summary["steps"] and summary["edits"] == 5
    # the re-run's records hold the same edits, at the same steps
    rerun = mimics.load_run(tmp_path / "again")
    edits = rerun.events[rerun.events.kind == "edit"]
    assert edits[["step", "robot", "detail"]].values.tolist() == \
        rows[["step", "robot", "detail"]].values.tolist()


def test_the_unedited_run_differs(tmp_path, monkeypatch):
    """The digest sees the edits: the same scenario and seed without them end elsewhere."""
    folder = live_edited_run(tmp_path)
    source = tmp_path / "edited.toml"
    monkeypatch.chdir(tmp_path)
    plain = CliRunner().invoke(cli.app, ["run", str(source), "go_to_goal", "--seed", "4",
                                         "--out", "plain"])
    assert plain.exit_code == 0, plain.output
    summary = json.loads((tmp_path / "plain" / "summary.json").read_text())
    assert summary["trajectory_digest"] != mimics.load_run(folder).summary["trajectory_digest"]


def test_a_run_edited_in_memory_keeps_its_edits(tmp_path):
    """Recorded in memory, then saved: the scenario holds the edits, and re-runs equal."""
    source = tmp_path / "edited.toml"
    source.write_text(SCENARIO)
    sim = prepare(source, "go_to_goal", seed=5)
    recorder = MemoryRecorder()
    sim.observers.append(recorder)
    sim.start()
    for _ in range(10):
        sim.step()
    sim.edit({"kind": "add_wall", "segment": [2.0, -2.0, 2.0, 0.5]})
    run = MemoryRun(recorder, sim.run())
    assert [(e.step, e.kind) for e in run.scenario.edits] == [(10, "add_wall")]
    folder = save_run(run, tmp_path / "saved")
    again = prepare(folder / "scenario.toml", "go_to_goal", seed=5).run()
    assert again.trajectory_digest == run.summary["trajectory_digest"]


def test_a_run_given_its_own_time_re_runs_as_long_from_its_folder(tmp_path, monkeypatch):
    """The record's settings hold the time the run was given, so the re-run needs no --time."""
    monkeypatch.chdir(tmp_path)
    first = CliRunner().invoke(cli.app, ["run", "line", "go_to_goal", "--robots", "3",
                                         "--time", "2.5", "--seed", "2", "--out", "first"])
    assert first.exit_code == 0, first.output
    again = CliRunner().invoke(cli.app, ["run", "first/scenario.toml", "go_to_goal",
                                         "--seed", "2", "--out", "again"])
    assert again.exit_code == 0, again.output
    one, two = (json.loads((tmp_path / name / "summary.json").read_text())
                for name in ("first", "again"))
    assert one["steps"] == two["steps"] == 25
    assert one["trajectory_digest"] == two["trajectory_digest"]
