"""The live runs' API: a run in a worker process, stepped, edited, stopped and recorded in a
run folder that re-runs bit for bit; the guards of the WebSocket; the errors."""

from __future__ import annotations

import json
import math
import struct
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fastapi.testclient import TestClient
from starlette.websockets import WebSocketDisconnect

from mimics.interfaces.web.app import create_app
from mimics.records.run_folder import load_run
from mimics.records.runner import prepare, run_to_folder
from tests.interfaces.web.test_web_api import scenario_body

RAISES = "def step(robot):\n    raise ValueError('no way forward')\n"


@pytest.fixture
def live_client(workspace: Path) -> Iterator[TestClient]:
    """The app on ``workspace`` with scenarios/two.toml saved (2 robots, 2 s, a 10 x 6 m room)
    and algorithms/raises.py; its live runs' workers end with it."""
    (workspace / "algorithms").mkdir(exist_ok=True)
    (workspace / "algorithms" / "raises.py").write_text(RAISES)
    with TestClient(create_app(workspace, hosts={"testserver"})) as client:
        assert client.put("/api/scenarios/file", json=scenario_body()).status_code == 200
        yield client


def wait_for(client: TestClient, run_id: int, *states: str) -> dict[str, Any]:
    """The live run's state once it is one of ``states`` (a bound only against a hang)."""
    for _ in range(3000):
        answer = client.get(f"/api/live/{run_id}").json()
        if answer["state"] in states:
            return answer
        time.sleep(0.05)
    raise AssertionError(f"live run {run_id} stayed {answer['state']}")


def poses_of(frame: bytes) -> tuple[float, np.ndarray, np.ndarray]:
    """Time, poses (n, 3) and states of one frame in the replay's layout."""
    count, robots = struct.unpack_from("<II", frame)
    assert count == 1
    sim_time = np.frombuffer(frame, "<f4", 1, 8)[0]
    poses = np.frombuffer(frame, "<f4", robots * 3, 12).reshape(robots, 3)
    states = np.frombuffer(frame, np.uint8, robots, 12 + 12 * robots)
    assert len(frame) == 12 + 13 * robots
    return float(sim_time), poses, states


def test_a_live_run_steps_is_edited_and_its_folder_reruns_bit_for_bit(
        live_client: TestClient, workspace: Path) -> None:
    client = live_client
    started = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                             "algorithm": "go_to_goal", "seed": 3,
                                             "paused": True, "speed": "fastest"})
    assert started.status_code == 200, started.text
    run = started.json()
    assert (run["state"], run["step"], run["run"]) == ("paused", 0, "runs/two-go_to_goal-s3")
    run_id = run["id"]
    dt = client.get(f"/api/live/{run_id}/meta").json()["dt"]
    assert dt == 0.1  # the scenario's default step
    # Step: exactly one step, then paused
    after = client.post(f"/api/live/{run_id}/step").json()
    assert (after["state"], after["step"]) == ("paused", 1)
    assert after["time"] == pytest.approx(dt, abs=1e-12)
    after = client.post(f"/api/live/{run_id}/step").json()
    assert after["step"] == 2 and after["time"] == pytest.approx(2 * dt, abs=1e-12)
    # a drag: robot 1 to (5, 4.5), its heading kept; the frame shows it at once (paused)
    moved = client.post(f"/api/live/{run_id}/edit", json={"kind": "move_robot", "robot": 1,
                                                          "x": 5.0, "y": 4.5})
    assert moved.status_code == 200, moved.text
    assert moved.json()["step"] == 2
    _, poses, _ = poses_of(client.get(f"/api/live/{run_id}/frame").content)
    assert poses[1, :2].tolist() == [5.0, 4.5]
    # a wall across the room's middle (x = 4), clear of both robots
    walls = len(client.get(f"/api/live/{run_id}/meta").json()["map"]["segments"])
    wall = client.post(f"/api/live/{run_id}/edit", json={"kind": "add_wall",
                                                         "segment": [4.0, 0.5, 4.0, 2.5]})
    assert wall.status_code == 200, wall.text
    segments = client.get(f"/api/live/{run_id}/meta").json()["map"]["segments"]
    assert len(segments) == walls + 1 and segments[-1] == [4.0, 0.5, 4.0, 2.5]
    # refused: a robot onto the new wall; one line, and the run goes on unchanged
    refused = client.post(f"/api/live/{run_id}/edit", json={"kind": "move_robot", "robot": 0,
                                                            "x": 4.0, "y": 1.5})
    assert refused.status_code == 422
    assert "\n" not in refused.json()["detail"] and refused.json()["detail"]
    bad_kind = client.post(f"/api/live/{run_id}/edit", json={"kind": "teleport"})
    assert bad_kind.status_code == 422 and "move_robot" in bad_kind.json()["detail"]
    # Resume to the end (2 s): robot 0 meets the wall it now has to go around
    client.post(f"/api/live/{run_id}/resume")
    end = wait_for(client, run_id, "finished", "error")
    assert (end["state"], end["status"], end["error"]) == ("finished", "time_limit", "")
    assert client.post(f"/api/live/{run_id}/pause").status_code == 409
    assert client.post(f"/api/live/{run_id}/edit", json={"kind": "remove_robot",
                                                         "robot": 0}).status_code == 409
    folder = workspace / end["run"]
    recorded = load_run(folder)
    edits = recorded.events[recorded.events["kind"] == "edit"]
    assert len(edits) == 2  # the refused edit is not in the records
    assert "[[edits]]" in (folder / "scenario.toml").read_text()
    # the folder's scenario.toml, the algorithm and the seed re-run the edited run
    again = run_to_folder(prepare(folder / "scenario.toml", "go_to_goal", seed=3),
                          workspace / "again")
    assert again.trajectory_digest == recorded.summary["trajectory_digest"]
    # two live runs of one scenario leave two folders; Stop ends one, its folder complete
    second = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                            "algorithm": "go_to_goal", "seed": 3,
                                            "paused": True}).json()
    assert second["run"] == "runs/two-go_to_goal-s3-2"
    client.post(f"/api/live/{second['id']}/stop")
    stopped = wait_for(client, second["id"], "finished", "error")
    assert stopped["status"] == "stopped"
    assert load_run(workspace / stopped["run"]).summary["status"] == "stopped"
    listed = client.get("/api/live").json()["live"]
    assert [r["id"] for r in listed] == [second["id"], run_id]


def test_the_stream_sends_meta_state_and_frames_and_refuses_other_sites(
        live_client: TestClient) -> None:
    client = live_client
    run = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                         "algorithm": "go_to_goal", "paused": True}).json()
    path = f"/api/live/{run['id']}/stream"
    for headers in ({"Origin": "http://evil.example"}, {"Host": "evil.example"}):
        with pytest.raises(WebSocketDisconnect) as refused, \
                client.websocket_connect(path, headers=headers):
            pass
        assert refused.value.code == 1008
    with pytest.raises(WebSocketDisconnect) as unknown, \
            client.websocket_connect("/api/live/999/stream"):
        pass
    assert unknown.value.reason == "no live run 999"
    with client.websocket_connect(path, headers={"Origin": "http://testserver"}) as socket, \
            client.websocket_connect(path) as other:  # a second page watching the same run
        meta = json.loads(socket.receive_text())
        assert meta["type"] == "meta" and meta["robots"] == 2
        assert meta["goals"] == [[8.0, 1.5], None]
        state = json.loads(socket.receive_text())
        assert (state["type"], state["state"], state["id"]) == ("state", "paused", run["id"])
        sim_time, poses, states = poses_of(socket.receive_bytes())
        assert sim_time == 0.0 and poses[:, :2].tolist() == [[1.0, 1.5], [1.0, 3.0]]
        assert states.tolist() == [0, 0]
        assert [json.loads(other.receive_text())["type"] for _ in "ms"] == ["meta", "state"]
        assert poses_of(other.receive_bytes())[0] == 0.0
        client.post(f"/api/live/{run['id']}/step")
        assert poses_of(socket.receive_bytes())[0] == pytest.approx(0.1)
        assert poses_of(other.receive_bytes())[0] == pytest.approx(0.1)
        assert client.get(f"/api/live/{run['id']}").json()["watchers"] == 2
    # the inspector's fields of robot 0, now (after one step)
    robot = client.get(f"/api/live/{run['id']}/robot", params={"robot": 0}).json()
    assert (robot["id"], robot["type"], robot["state"], robot["goal"]) == (
        0, "Pioneer2DX", "active", [8.0, 1.5])
    assert robot["time"] == pytest.approx(0.1) and robot["x"] > 1.0 and robot["v"] > 0
    assert robot["lines"] == [] and robot["skipped"] == 0
    missing = client.get(f"/api/live/{run['id']}/robot", params={"robot": 2})
    assert missing.status_code == 422 and missing.json()["detail"] == (
        "robot 2: the run has robots 0..1")
    # closing the page does not stop the run
    assert client.get(f"/api/live/{run['id']}").json()["state"] == "paused"
    client.post(f"/api/live/{run['id']}/stop")


def test_bad_requests_get_one_line(live_client: TestClient) -> None:
    client = live_client
    assert client.get("/api/live/7").status_code == 404
    assert client.post("/api/live/7/pause").status_code == 404
    assert client.post("/api/live/7/edit", json={"kind": "remove_robot",
                                                 "robot": 0}).status_code == 404
    for body, status in (({"scenario": "scenarios/none.toml", "algorithm": "go_to_goal"}, 400),
                         ({"scenario": "../x.toml", "algorithm": "go_to_goal"}, 400),
                         ({"scenario": "line", "algorithm": "algorithms/../x.py"}, 400),
                         ({"scenario": "line", "algorithm": "go_to_goal", "speed": 1000}, 422),
                         ({"scenario": "line", "algorithm": "go_to_goal", "speed": "slow"},
                          422),
                         ({"algorithm": "go_to_goal"}, 422)):
        answer = client.post("/api/live", json=body)
        assert answer.status_code == status, (body, answer.text)
        assert "\n" not in answer.json()["detail"]
    # refused in the worker, before anything runs: the runner's own one line
    too_long = client.post("/api/live", json={"scenario": "line", "algorithm": "go_to_goal",
                                              "time": 1e12})
    assert too_long.status_code == 422 and too_long.json()["detail"].startswith("time")
    huge = client.post("/api/live/1/edit", content=b"{" + b" " * 3_000_000 + b"}",
                       headers={"Content-Type": "application/json"})
    assert huge.status_code == 413  # the body limit holds for the live routes too
    foreign = client.post("/api/live", json={"scenario": "line", "algorithm": "go_to_goal"},
                          headers={"Origin": "http://evil.example"})
    assert foreign.status_code == 403
    assert "/api/live/{run_id}/edit" in client.get("/openapi.json").json()["paths"]


def test_an_algorithm_that_raises_ends_the_run_with_the_clis_error(
        live_client: TestClient, workspace: Path) -> None:
    client = live_client
    run = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                         "algorithm": "algorithms/raises.py"}).json()
    end = wait_for(client, run["id"], "finished", "error")
    assert end["state"] == "error"
    # the CLI prints summary.json's error: the same text, its paths workspace-relative
    cli = run_to_folder(prepare(workspace / "scenarios" / "two.toml",
                                workspace / "algorithms" / "raises.py"), workspace / "cli")
    assert cli.error.startswith(f"ValueError in robot 0 at t=0 s, {workspace}/algorithms/")
    assert end["error"] == cli.error.replace(f"{workspace}/", "")
    assert load_run(workspace / end["run"]).summary["error"] == cli.error


def test_an_algorithm_that_hangs_is_stopped_at_the_wall_limit_as_in_the_cli(
        live_client: TestClient, workspace: Path) -> None:
    hang = workspace / "algorithms" / "hangs.py"
    hang.write_text("def step(robot):\n    while True:\n        pass\n")
    client = live_client
    run = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                         "algorithm": "algorithms/hangs.py",
                                         "wall_limit": 0.5}).json()
    end = wait_for(client, run["id"], "finished", "error")
    cli = run_to_folder(prepare(workspace / "scenarios" / "two.toml", hang, wall_limit=0.5),
                        workspace / "cli")
    assert (end["state"], end["status"]) == ("error", "wall_limit")
    assert end["error"] == cli.error.replace(f"{workspace}/", "")
    assert "did not return within the wall limit of 0.5 s" in cli.error


def test_stop_ends_the_worker_of_a_step_that_never_returns(
        live_client: TestClient, workspace: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from mimics.interfaces.web import live_runs

    monkeypatch.setattr(live_runs, "STOP_GRACE", 1.0)
    inside = workspace / "inside"  # written once the step is under way: Stop comes after
    (workspace / "algorithms" / "hangs.py").write_text(
        f"def step(robot):\n    open({str(inside)!r}, 'w').close()\n    while True:\n"
        "        pass\n")
    client = live_client
    run = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                         "algorithm": "algorithms/hangs.py"}).json()
    assert run["state"] == "running"
    deadline = time.monotonic() + 60
    while not inside.exists():
        assert time.monotonic() < deadline, "the algorithm's step never started"
        time.sleep(0.05)
    assert client.post(f"/api/live/{run['id']}/stop").status_code == 200
    end = wait_for(client, run["id"], "finished", "error")
    assert end["state"] == "error"
    assert end["error"] == ("stopped: step 1 did not return within 1 s of Stop; the worker "
                            "was ended (the run folder keeps what was recorded, without "
                            "summary.json)")
    folder = workspace / end["run"]
    assert (folder / "scenario.toml").is_file() and not (folder / "summary.json").exists()


#: Two robots in the 10 x 6 m room, noise off, 3 beams over 180 degrees (right, ahead,
#: left): robot 0 at (7, 3) faces the east wall, robot 1 at (2, 3) the west wall.
FACING_WALLS = """name = "facing"
map = "../maps/room.txt"

[types.Three]
base = "Pioneer2DX"
ranger = { beams = 3 }

[[robots]]
type = "Three"
x = 7.0
y = 3.0

[[robots]]
type = "Three"
x = 2.0
y = 3.0
yaw = 3.141592653589793

[settings]
time_limit = 5.0
noise = "off"
"""


def test_beams_are_the_last_scan_the_engine_sensed(live_client: TestClient,
                                                   workspace: Path) -> None:
    (workspace / "scenarios" / "facing.toml").write_text(FACING_WALLS)
    client = live_client
    run = client.post("/api/live", json={"scenario": "scenarios/facing.toml",
                                         "algorithm": "go_to_goal", "paused": True})
    assert run.status_code == 200, run.text
    run_id = run.json()["id"]
    assert client.post(f"/api/live/{run_id}/step").json()["step"] == 1
    # robot 0 (no goal: it stays) sees, by hand: the south wall 3 m to its right, the east
    # wall 3 m ahead, the north wall 3 m to its left; each beam from its centre (7, 3)
    beams = client.get(f"/api/live/{run_id}/beams", params={"robot": 0})
    assert beams.status_code == 200, beams.text
    got = beams.json()
    assert (got["step"], got["every"]) == (1, 1)
    assert got["time"] == pytest.approx(0.1)
    assert np.array(got["segments"]) == pytest.approx(np.array(
        [[7, 3, 7, 0], [7, 3, 10, 3], [7, 3, 7, 6]]), abs=1e-4)
    middle = got["segments"][1]
    assert math.dist(middle[:2], middle[2:]) == pytest.approx(3.0, abs=1e-4)
    # every active robot's: robot 1 at (2, 3) faces west: the west wall 2 m ahead
    every = client.get(f"/api/live/{run_id}/beams", params={"all": "true"}).json()
    assert np.array(every["segments"]) == pytest.approx(np.array(
        [[7, 3, 7, 0], [7, 3, 10, 3], [7, 3, 7, 6],
         [2, 3, 2, 6], [2, 3, 0, 3], [2, 3, 2, 0]]), abs=1e-4)
    # a removed robot has no scan: robot 1's beams go, robot 0's stay
    client.post(f"/api/live/{run_id}/edit", json={"kind": "remove_robot", "robot": 1})
    assert client.get(f"/api/live/{run_id}/beams",
                      params={"robot": 1}).json()["segments"] == []
    assert len(client.get(f"/api/live/{run_id}/beams",
                          params={"all": "true"}).json()["segments"]) == 3
    # bad requests: one line each
    for params, status in (({"robot": 2}, 422), ({"robot": -1}, 422), ({}, 422),
                           ({"robot": 0, "all": "true"}, 422), ({"robot": "x"}, 422)):
        answer = client.get(f"/api/live/{run_id}/beams", params=params)
        assert answer.status_code == status, (params, answer.text)
    assert client.get(f"/api/live/{run_id}/beams", params={"robot": 2}).json()["detail"] == (
        "robot 2: the run has robots 0..1")
    assert client.get("/api/live/99/beams", params={"robot": 0}).status_code == 404
    assert "/api/live/{run_id}/beams" in client.get("/openapi.json").json()["paths"]
    client.post(f"/api/live/{run_id}/stop")


def test_live_beams_carry_the_scans_noise_and_leave_the_run_unchanged(
        live_client: TestClient, workspace: Path) -> None:
    from mimics.interfaces.replay.beams import BeamCaster

    client = live_client  # wall_aware reads its scan each step: the live trace comes first
    run = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                         "algorithm": "wall_aware", "seed": 5,
                                         "paused": True, "speed": "fastest"}).json()
    headless = prepare(workspace / "scenarios" / "two.toml", "wall_aware", seed=5)
    caster = BeamCaster(headless.scenario)
    for _ in range(3):  # beams asked at every step: the trace comes earlier than the algorithm's
        client.post(f"/api/live/{run['id']}/step")
        headless.step()
        got = np.array(client.get(f"/api/live/{run['id']}/beams",
                                  params={"all": "true"}).json()["segments"])
        state = headless.state
        # the headless run's scan at the same step, noise included: the same beam ends
        ranges = np.concatenate([state.scan[i][np.isfinite(state.scan[i])] for i in (0, 1)])
        assert np.hypot(got[:, 2] - got[:, 0], got[:, 3] - got[:, 1]) == pytest.approx(
            ranges, abs=2e-4)
        # ...which are not the noise-free ranges (Pioneer2DX: sigma 0.015 m)
        exact = np.concatenate([caster.beams(i, state.pose, state.status) for i in (0, 1)])
        off = np.hypot(*(got[:, 2:] - exact[:, 1]).T)
        assert 0.005 < np.median(off[ranges < 7.9]) < 0.05
    client.post(f"/api/live/{run['id']}/resume")
    end = wait_for(client, run["id"], "finished", "error")
    again = run_to_folder(prepare(workspace / "scenarios" / "two.toml", "wall_aware", seed=5),
                          workspace / "again")
    assert load_run(workspace / end["run"]).summary["trajectory_digest"] == (
        again.trajectory_digest)
