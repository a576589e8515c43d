"""Nothing the page writes replaces earlier work silently: a run gets a new folder when its
name is taken, and saving over an existing map or scenario needs ``overwrite``."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from fastapi.testclient import TestClient

from mimics.records.run_folder import load_run
from mimics.world.map_files import load_map
from tests.interfaces.web.test_web_api import scenario_body, wait


def run_once(client: TestClient, path: str) -> dict[str, Any]:
    job = client.post("/api/scenarios/run", json={"path": path, "algorithm": "go_to_goal",
                                                  "seed": 4, "time": 0.5}).json()
    done = wait(client, job["id"])
    assert done["state"] == "done", done
    return done["result"]


def test_two_scenarios_of_one_name_leave_two_run_folders(client: TestClient, workspace: Path
                                                         ) -> None:
    client.put("/api/scenarios/file", json=scenario_body())
    client.put("/api/scenarios/file", json=scenario_body(
        path="scenarios/copy.toml", robots=[{"type": "Pioneer2DX", "x": 5.0, "y": 3.0}]))
    first = run_once(client, "scenarios/two.toml")
    summary = (workspace / first["run"] / "summary.json").read_bytes()
    second = run_once(client, "scenarios/copy.toml")  # also called "two"
    third = run_once(client, "scenarios/two.toml")
    assert [first["run"], second["run"], third["run"]] == [
        "runs/two-go_to_goal-s4", "runs/two-go_to_goal-s4-2", "runs/two-go_to_goal-s4-3"]
    assert (workspace / first["run"] / "summary.json").read_bytes() == summary
    assert [load_run(workspace / r["run"]).summary["robots"]
            for r in (first, second, third)] == [2, 1, 2]
    listed = {r["path"] for r in client.get("/api/runs").json()["runs"]}
    assert {first["run"], second["run"], third["run"]} <= listed


def test_saving_over_another_file_needs_overwrite(client: TestClient, workspace: Path) -> None:
    assert client.put("/api/scenarios/file", json=scenario_body()).status_code == 200
    text = (workspace / "scenarios" / "two.toml").read_text()
    again = client.put("/api/scenarios/file", json=scenario_body(name="x", overwrite=False))
    assert again.status_code == 409 and (workspace / "scenarios" / "two.toml").read_text() == text
    assert client.put("/api/scenarios/file", json=scenario_body(name="x")).status_code == 200
    assert 'name = "x"' in (workspace / "scenarios" / "two.toml").read_text()
    body = {"path": "maps/room.txt", "name": "other", "bounds": [0, 0, 4, 4],
            "segments": [[0, 0, 4, 0]], "overwrite": False}
    refused = client.put("/api/maps/file", json=body)
    assert refused.status_code == 409
    assert refused.json()["detail"] == "maps/room.txt exists already: replace it?"
    assert len(load_map(workspace / "maps" / "room.txt").segments) == 4  # the room, kept
    assert client.put("/api/maps/file", json={**body, "path": "maps/new.txt"}
                      ).status_code == 200  # a new file needs no question
    assert client.put("/api/maps/file", json={**body, "overwrite": True}).status_code == 200
    assert load_map(workspace / "maps" / "room.txt").segments.tolist() == [[0, 0, 4, 0]]
