"""A live run ends every way it can (its time limit, Stop while running, Stop while paused,
a pause the server ends at the wall limit, an error in the algorithm), and each one's folder
re-runs bit for bit with ``mimics run RUN/scenario.toml ALGO --seed S``, no other option:
the same status, the same step, the same trajectory digest. Stop answers once the run has
ended; the inspector's reads of an ended run are answered, not refused."""

from __future__ import annotations

import json
import time
import tomllib
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from typer.testing import CliRunner

from mimics.interfaces.cli import app
from mimics.interfaces.web.app import create_app
from mimics.records.run_folder import load_run
from tests.interfaces.web.test_live_api import wait_for
from tests.interfaces.web.test_web_api import scenario_body

# raises in robot 0 at t = 0.5 s: the run ends in error at step 5
LATE_ERROR = ("def step(robot):\n"
              "    if robot.id == 0 and robot.time > 0.45:\n"
              "        raise ValueError('late')\n"
              "    return 0.5, 0.0\n")


@pytest.fixture
def live(workspace: Path) -> Iterator[TestClient]:
    """The app on ``workspace`` with scenarios/two.toml (2 robots, 60 s, a 10 x 6 m room)
    and algorithms/late.py."""
    (workspace / "algorithms").mkdir(exist_ok=True)
    (workspace / "algorithms" / "late.py").write_text(LATE_ERROR)
    with TestClient(create_app(workspace, hosts={"testserver"})) as client:
        body = scenario_body(settings={"time_limit": 60.0})
        assert client.put("/api/scenarios/file", json=body).status_code == 200
        yield client


def start(client: TestClient, algorithm: str = "go_to_goal", **options: Any) -> int:
    answer = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                            "algorithm": algorithm, "seed": 4, **options})
    assert answer.status_code == 200, answer.text
    return int(answer.json()["id"])


def rerun(workspace: Path, folder: Path, algorithm: str, out: str) -> dict[str, Any]:
    """``mimics run FOLDER/scenario.toml ALGORITHM --seed 4``: its summary.json."""
    result = CliRunner().invoke(app, ["run", str(folder / "scenario.toml"), algorithm,
                                      "--seed", "4", "--out", str(workspace / out)])
    assert result.exit_code in (0, 1), result.output  # (1: the run ended in error)
    return json.loads((workspace / out / "summary.json").read_text())


def ended_the_same(workspace: Path, end: dict[str, Any], algorithm: str) -> dict[str, Any]:
    folder = workspace / end["run"]
    recorded = load_run(folder).summary
    again = rerun(workspace, folder, algorithm, f"again-{end['id']}")
    for key in ("status", "steps", "sim_time", "trajectory_digest"):
        assert again[key] == recorded[key], key
    assert (recorded["status"], recorded["steps"]) == (end["status"], end["step"])
    return recorded


def test_every_end_of_a_live_run_reruns_from_its_folder(live: TestClient,
                                                        workspace: Path) -> None:
    client = live
    ends: dict[str, dict[str, Any]] = {}
    # its time limit (1 s)
    run = start(client, speed="fastest", time=1.0)
    ends["time_limit"] = wait_for(client, run, "finished", "error")
    # Stop while running (at real time): the answer is the ended run, folder complete
    run = start(client, speed=1.0)
    time.sleep(0.6)
    stopped = client.post(f"/api/live/{run}/stop").json()
    assert (stopped["state"], stopped["status"]) == ("finished", "stopped")
    assert (workspace / stopped["run"] / "summary.json").exists()
    assert stopped["step"] > 0
    ends["stop_running"] = stopped
    # Stop while paused, after three steps: it ends at step 3, no step more
    run = start(client, paused=True)
    for _ in range(3):
        client.post(f"/api/live/{run}/step")
    stopped = client.post(f"/api/live/{run}/stop").json()
    assert (stopped["state"], stopped["status"], stopped["step"]) == ("finished", "stopped", 3)
    ends["stop_paused"] = stopped
    # a pause the server ends: paused past its wall limit (pauses count), it ends there
    run = start(client, paused=True, wall_limit=1.0)
    client.post(f"/api/live/{run}/step")
    ends["wall_limit"] = wait_for(client, run, "finished", "error")
    assert (ends["wall_limit"]["status"], ends["wall_limit"]["step"]) == ("wall_limit", 1)
    # an error in the algorithm
    run = start(client, "algorithms/late.py", speed="fastest")
    ends["error"] = wait_for(client, run, "finished", "error")
    assert (ends["error"]["state"], ends["error"]["status"]) == ("error", "error")
    for how, end in ends.items():
        algorithm = str(workspace / "algorithms" / "late.py") if how == "error" \
            else "go_to_goal"
        recorded = ended_the_same(workspace, end, algorithm)
        edits = tomllib.loads((workspace / end["run"] / "scenario.toml").read_text()).get(
            "edits", [])
        if how in ("stop_running", "stop_paused", "wall_limit"):  # the end, recorded
            assert edits == [{"step": end["step"], "kind": "end", "status": end["status"]}]
            assert f"t = {end['step'] * 0.1:g} s" in (
                workspace / end["run"] / "scenario.toml").read_text()
        else:  # the engine's own ends need no record
            assert edits == []
        # the engine's time apart from the pacing and pauses
        assert 0 < recorded["wall_time"] <= recorded["paced_wall_time"]
        assert "paced wall time" in (workspace / end["run"] / "summary.txt").read_text()
    assert ends["stop_running"]["step"] < 600 and ends["time_limit"]["step"] == 10


def test_the_inspectors_reads_of_an_ended_run_are_answered(live: TestClient) -> None:
    client = live
    run = start(client, paused=True)
    client.post(f"/api/live/{run}/step")
    seen = client.get(f"/api/live/{run}/robot", params={"robot": 0}).json()
    stopped = client.post(f"/api/live/{run}/stop").json()
    assert stopped["state"] == "finished"
    again = client.get(f"/api/live/{run}/robot", params={"robot": 0})
    assert again.status_code == 200 and again.json() == {**seen, "final": True}
    other = client.get(f"/api/live/{run}/robot", params={"robot": 1}).json()
    assert other["final"] and other["state"] == "active" and other["time"] == seen["time"]
    beams = client.get(f"/api/live/{run}/beams", params={"robot": 0})
    assert beams.status_code == 200 and beams.json()["final"] and beams.json()["segments"] == []
    assert client.get(f"/api/live/{run}/robot", params={"robot": 2}).status_code == 422
    # a second Stop and the controls: the run has ended
    assert client.post(f"/api/live/{run}/stop").status_code == 409
    assert client.post(f"/api/live/{run}/resume").status_code == 409


def test_edits_are_recorded_at_the_millimetre_and_read_back_exactly(live: TestClient,
                                                                    workspace: Path) -> None:
    client = live
    run = start(client, paused=True)
    moved = client.post(f"/api/live/{run}/edit", json={
        "kind": "move_robot", "robot": 1, "x": 5.0000003317128052, "y": 4.4996,
        "yaw": 0.78539816})
    assert moved.status_code == 200, moved.text
    assert (moved.json()["x"], moved.json()["y"], moved.json()["yaw"]) == (5.0, 4.5, 0.785)
    wall = client.post(f"/api/live/{run}/edit", json={
        "kind": "add_wall", "segment": [6.50012, 0.29999, 6.5, 2.5004]})
    assert wall.json()["segment"] == [6.5, 0.3, 6.5, 2.5]
    end = client.post(f"/api/live/{run}/stop").json()
    text = (workspace / end["run"] / "scenario.toml").read_text()
    assert "x = 5.0\ny = 4.5\nyaw = 0.785\n" in text
    assert "segment = [6.5, 0.3, 6.5, 2.5]" in text
    ended_the_same(workspace, end, "go_to_goal")
