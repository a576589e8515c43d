"""Issue 53: a refused request never changes or ends a live run; a live run that ends in
error still closes its folder; unknown keys, enormous numbers and odd types are refused
with one line naming the field."""

from __future__ import annotations

import json
import multiprocessing
import tomllib
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.interfaces.web.live_worker import LiveWorker
from mimics.records.recorder import RunRecorder
from mimics.records.run_folder import load_run
from mimics.records.runner import prepare, run_to_folder
from mimics.world.edits import EditError, edit_from_dict
from mimics.world.limits import coordinate_limits
from tests.interfaces.web.test_live_api import live_client, wait_for  # noqa: F401 (fixture)

BOUNDS = (0.0, 0.0, 10.0, 6.0)


def test_an_enormous_wall_is_refused_and_the_live_run_goes_on_to_a_complete_folder(
        live_client: TestClient, workspace: Path) -> None:  # noqa: F811
    client = live_client
    run = client.post("/api/live", json={"scenario": "scenarios/two.toml",
                                         "algorithm": "go_to_goal", "seed": 3,
                                         "paused": True, "speed": "fastest"}).json()
    run_id = run["id"]
    client.post(f"/api/live/{run_id}/step")
    removed = client.post(f"/api/live/{run_id}/edit", json={"kind": "remove_robot", "robot": 0})
    assert removed.status_code == 200, removed.text
    walls = client.get(f"/api/live/{run_id}/meta").json()["map"]["segments"]
    refused = client.post(f"/api/live/{run_id}/edit", json={
        "kind": "add_wall", "segment": [1e300, 1e300, -1e300, 5.0]})
    assert refused.status_code == 422
    # the room is 10 x 6 m: the margin is 10 m on each side
    assert refused.json()["detail"] == (
        "edit.segment: expected x from -10 to 20 and y from -10 to 16 (the map's bounds plus "
        "a margin), got [1e+300, 1e+300, -1e+300, 5]")
    now = client.get(f"/api/live/{run_id}").json()
    assert (now["state"], now["step"], now["error"]) == ("paused", 1, "")
    assert client.get(f"/api/live/{run_id}/meta").json()["map"]["segments"] == walls
    client.post(f"/api/live/{run_id}/resume")
    end = wait_for(client, run_id, "finished", "error")
    assert (end["state"], end["status"]) == ("finished", "time_limit")
    folder = workspace / end["run"]
    recorded = load_run(folder)
    assert recorded.summary["edits"] == 1
    edits = tomllib.loads((folder / "scenario.toml").read_text())["edits"]
    assert [e["kind"] for e in edits] == ["remove_robot"]
    again = run_to_folder(prepare(folder / "scenario.toml", "go_to_goal", seed=3),
                          workspace / "again")
    assert again.trajectory_digest == recorded.summary["trajectory_digest"]


def test_a_live_run_whose_stepper_raises_closes_its_folder_with_summary_and_edits(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    sim = prepare("line", "go_to_goal", robots=2, time=2.0, seed=1)
    folder = tmp_path / "run"
    recorder = RunRecorder(folder)
    sim.observers.append(recorder)
    ours, theirs = multiprocessing.Pipe(duplex=False)
    worker = LiveWorker(sim, recorder, folder, theirs, speed=float("inf"), fps=60.0,
                        paused=True)
    worker.stepper.step()
    worker.stepper.wait_paused()
    worker.stepper.edit({"kind": "remove_robot", "robot": 0})

    def broken(*args: Any) -> None:  # a bug in the engine, not a refusal
        raise ValueError("cell must be a positive number, got None")

    monkeypatch.setattr(sim, "_set_walls", broken)
    with pytest.raises(ValueError):
        worker.stepper.edit({"kind": "add_wall", "segment": [4.0, 4.0, 5.0, 5.0]})
    worker.finish()
    messages = []
    while ours.poll(0.1):
        messages.append(ours.recv())
    end = messages[-1]
    assert end[0] == "end" and end[1]["status"] == "error"
    assert end[1]["error"] == "ValueError: cell must be a positive number, got None"
    summary = json.loads((folder / "summary.json").read_text())
    assert (summary["status"], summary["edits"]) == ("error", 1)
    edits = tomllib.loads((folder / "scenario.toml").read_text())["edits"]
    assert [(e["kind"], e["step"]) for e in edits] == [("remove_robot", 1)]


@pytest.mark.parametrize(("method", "route", "body", "named"), [
    ("post", "/api/live", {"scenario": "line", "algorithm": "go_to_goal", "seeed": 5},
     "seeed: unknown field (expected scenario, algorithm, seed, time, speed, wall_limit, "
     "paused, fps, battery, run)"),
    ("post", "/api/live/1/speed", {"speed": 2, "fast": True},
     "fast: unknown field (expected speed)"),
    ("post", "/api/live/1/step", {"steps": 5}, "steps: unknown field (this action takes no "
                                                "fields)"),
    ("post", "/api/batteries", {"name": "b", "algorithms": ["go_to_goal"],
                                "scenarios": [{"name": "line", "parms": {}}]},
     "scenarios[0].parms: unknown field (expected name, params)"),
    ("post", "/api/batteries/resume", {"path": "batteries/b", "force": 1},
     "force: unknown field (expected path)"),
    ("post", "/api/runs/export", {"path": "runs/x", "sped": 2},
     "sped: unknown field (expected path, speed, fps, robot)"),
    ("post", "/api/scenarios/run", {"path": "scenarios/x.toml", "algorithm": "a", "seeds": 1},
     "seeds: unknown field (expected path, algorithm, seed, time, wall_limit)"),
    ("put", "/api/maps/file", {"path": "maps/x.txt", "bounds": [0, 0, 1, 1], "walls": []},
     "walls: unknown field (expected path, name, bounds, segments, overwrite)"),
])
def test_unknown_keys_are_refused_by_name(client: TestClient, method: str, route: str,
                                          body: dict[str, Any], named: str) -> None:
    answer = getattr(client, method)(route, json=body)
    assert (answer.status_code, answer.json()["detail"]) == (422, named)


@pytest.mark.parametrize("metric", [{"a": 1}, ["time_to_goal"], 5])
def test_a_stopping_rule_metric_of_another_type_is_a_4xx(client: TestClient,
                                                         metric: Any) -> None:
    answer = client.post("/api/batteries", json={
        "name": "b", "algorithms": ["go_to_goal"], "scenarios": [{"name": "line"}],
        "until": {"metric": metric, "half_width": 0.2}, "dry_run": True})
    assert 400 <= answer.status_code < 500
    assert "metric" in answer.json()["detail"] or "battery" in answer.json()["detail"]


@pytest.mark.parametrize(("body", "named"), [
    ({"bounds": [0, 0, 1e300, 1e300]}, "map.bounds: expected sides of at most 1e+06 m"),
    ({"bounds": [0, 0, 10, 6], "segments": [[0, 0, 1e300, 1]]},
     "map.segments[0]: expected x from -10 to 20 and y from -10 to 16"),
])
def test_a_map_too_large_to_simulate_is_not_saved(client: TestClient, workspace: Path,
                                                  body: dict[str, Any], named: str) -> None:
    answer = client.put("/api/maps/file", json={"path": "maps/huge.txt", **body})
    assert answer.status_code == 422 and answer.json()["detail"].startswith(named)
    assert not (workspace / "maps" / "huge.txt").exists()


@settings(derandomize=True, max_examples=200, deadline=None)
@given(st.lists(st.floats(-1e308, 1e308, allow_nan=False), min_size=4, max_size=4))
def test_an_edits_wall_is_taken_exactly_when_it_lies_within_the_margin(
        segment: list[float]) -> None:
    xlow, ylow, xhigh, yhigh = coordinate_limits(BOUNDS)  # (-10, -10, 20, 16), by hand
    assert (xlow, ylow, xhigh, yhigh) == (-10.0, -10.0, 20.0, 16.0)
    inside = all(-10 <= x <= 20 for x in segment[0::2]) and all(
        -10 <= y <= 16 for y in segment[1::2])
    data = {"kind": "add_wall", "segment": segment}
    if segment[:2] == segment[2:]:
        return  # refused for another reason (a wall of no length)
    if inside:
        assert edit_from_dict(data, bounds=BOUNDS).segment == tuple(segment)
    else:
        with pytest.raises(EditError, match=r"^edit\.segment: expected x from -10 to 20"):
            edit_from_dict(data, bounds=BOUNDS)
