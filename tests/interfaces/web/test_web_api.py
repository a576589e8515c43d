"""The workbench's JSON API, route by route, against the files the CLI reads and writes."""

from __future__ import annotations

import struct
import time
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq
from fastapi.testclient import TestClient

from mimics.records.run_folder import load_run
from mimics.world.map_files import load_map
from mimics.world.scenario_files import load_scenario_toml

SVG = (b'<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50">'
       b'<line x1="0" y1="0" x2="100" y2="0" stroke="black"/>'
       b'<polyline points="0,10 50,10 50,40" fill="none" stroke="black"/></svg>')


def wait(client: TestClient, job_id: int, limit: float = 90.0) -> dict[str, Any]:
    end = time.monotonic() + limit
    while time.monotonic() < end:
        job = client.get(f"/api/jobs/{job_id}").json()
        if job["state"] != "running":
            return job
        time.sleep(0.2)
    raise AssertionError(f"job {job_id} still running after {limit} s")


def test_the_page_and_the_openapi_schema_are_served(client: TestClient) -> None:
    page = client.get("/")
    assert page.status_code == 200 and ">Batteries</a>" in page.text
    assert client.get("/static/js/app.js").status_code == 200
    paths = client.get("/openapi.json").json()["paths"]
    for route in ("/api/maps/file", "/api/scenarios/run", "/api/batteries/status",
                  "/api/runs/frames", "/api/jobs/{job_id}"):
        assert route in paths
    assert client.get("/api/jobs/999").status_code == 404


def test_a_saved_map_is_the_file_the_cli_reads(client: TestClient, workspace: Path) -> None:
    walls = [[0.5, 0.5, 3.0, 0.5], [3.0, 0.5, 3.0, 2.25]]
    saved = client.put("/api/maps/file", json={"path": "maps/sub/l.txt", "name": "ell",
                                               "bounds": [0, 0, 4, 3], "segments": walls})
    assert saved.json()["walls"] == 2
    the_map = load_map(workspace / "maps" / "sub" / "l.txt")
    assert the_map.segments.tolist() == walls and the_map.bounds == (0, 0, 4, 3)
    opened = client.get("/api/maps/file", params={"path": "maps/sub/l.txt"}).json()
    assert opened["segments"] == walls and opened["name"] == "l"  # a .txt map is named by its stem
    client.put("/api/maps/file", json={"path": "maps/ell.toml", "name": "ell",
                                       "bounds": [0, 0, 4, 3], "segments": walls})
    assert load_map(workspace / "maps" / "ell.toml").name == "ell"  # .toml keeps the name
    listed = [f["path"] for f in client.get("/api/maps").json()["files"]]
    assert listed == ["maps/ell.toml", "maps/room.txt", "maps/sub/l.txt"]


def test_bad_maps_get_one_line_messages(client: TestClient, workspace: Path) -> None:
    (workspace / "maps" / "broken.txt").write_text("0 0 1\n")
    broken = client.get("/api/maps/file", params={"path": "maps/broken.txt"})
    assert broken.status_code == 422 and "line 1" in broken.json()["detail"]
    assert client.get("/api/maps/file", params={"path": "maps/none.txt"}).status_code == 404
    body = {"path": "maps/x.txt", "bounds": [0, 0, 4, 3], "segments": [[0, 0, 1]]}
    assert client.put("/api/maps/file", json=body).status_code == 422
    assert client.put("/api/maps/file", json={**body, "path": "runs/x.txt",
                                              "segments": []}).status_code == 400
    assert client.put("/api/maps/file", json={**body, "path": "maps/x.png",
                                              "segments": []}).status_code == 400
    inverted = client.put("/api/maps/file", json={**body, "bounds": [4, 0, 0, 3],
                                                  "segments": []})
    assert inverted.status_code == 422 and "xmin < xmax" in inverted.json()["detail"]
    assert client.get("/api/maps").status_code == 200  # the server goes on


def test_import_previews_walls_without_saving(client: TestClient, workspace: Path) -> None:
    response = client.post("/api/maps/import", params={"filename": "plan.svg",
                                                       "options": '{"scale": 0.1}'},
                           content=SVG)
    data = response.json()
    assert data["walls"] == 3 and data["path"] == ""
    ends = sorted(tuple(round(v, 6) for v in s) for s in data["segments"])
    # SVG's y axis points down: the importer flips it (10 m x 5 m drawing)
    assert ends == sorted([(0, 5, 10, 5), (0, 4, 5, 4), (5, 4, 5, 1)])
    assert sorted(p.name for p in (workspace / "maps").iterdir()) == ["room.txt"]
    for params, status in (({"filename": "plan.exe"}, 400), ({"filename": "a/plan.svg"}, 400),
                           ({"filename": "plan.svg", "options": "{"}, 400),
                           ({"filename": "plan.svg", "options": '{"evil": 1}'}, 400),
                           ({"filename": "map.yaml"}, 400)):
        assert client.post("/api/maps/import", params=params, content=SVG).status_code == status
    assert client.post("/api/maps/import", params={"filename": "a.svg"}).status_code == 400
    (workspace / "maps" / "plan.svg").write_bytes(SVG)
    again = client.post("/api/maps/import-file", params={"path": "maps/plan.svg",
                                                         "options": '{"scale": 0.1}'})
    assert again.json()["walls"] == 3


def scenario_body(**changes: Any) -> dict[str, Any]:
    body = {"path": "scenarios/two.toml", "name": "two", "map": "maps/room.txt",
            "robots": [{"type": "Pioneer2DX", "x": 1.0, "y": 1.5, "goal": [8.0, 1.5]},
                       {"type": "Pioneer2DX_b30", "x": 1.0, "y": 3.0, "yaw": 0.5,
                        "goal": None}],
            "types": {"Pioneer2DX_b30": {"base": "Pioneer2DX", "ranger": {"beams": 30}}},
            "settings": {"time_limit": 2.0}}
    return {**body, **changes}


def test_a_saved_scenario_is_the_file_the_cli_runs(client: TestClient, workspace: Path
                                                   ) -> None:
    assert client.put("/api/scenarios/file", json=scenario_body()).json() == {
        "path": "scenarios/two.toml", "robots": 2}
    scenario = load_scenario_toml(workspace / "scenarios" / "two.toml")
    assert scenario.stages[:, :3].tolist() == [[1.0, 1.5, 0.0], [1.0, 3.0, 0.5]]
    assert scenario.goals[0].tolist() == [8.0, 1.5] and np.isnan(scenario.goals[1]).all()
    assert scenario.robot_type(1).ranger.beams == 30 and scenario.settings.time_limit == 2.0
    assert scenario.map == load_map(workspace / "maps" / "room.txt")
    opened = client.get("/api/scenarios/file", params={"path": "scenarios/two.toml"}).json()
    assert opened["map"] == "maps/room.txt" and opened["robots"][1]["goal"] is None
    assert client.get("/api/scenarios").json()["files"] == ["scenarios/two.toml"]


def test_a_scenario_the_cli_would_refuse_is_not_saved(client: TestClient, workspace: Path
                                                      ) -> None:
    outside = scenario_body(robots=[{"type": "Pioneer2DX", "x": 20.0, "y": 1.0}])
    response = client.put("/api/scenarios/file", json=outside)
    assert response.status_code == 422 and "outside the map bounds" in response.json()["detail"]
    on_wall = scenario_body(robots=[{"type": "Pioneer2DX", "x": 0.05, "y": 1.0}])
    assert "touches wall" in client.put("/api/scenarios/file", json=on_wall).json()["detail"]
    unknown = scenario_body(robots=[{"type": "Tank", "x": 1.0, "y": 1.0}])
    assert client.put("/api/scenarios/file", json=unknown).status_code == 422
    assert client.put("/api/scenarios/file",
                      json=scenario_body(path="maps/s.toml")).status_code == 400
    assert client.put("/api/scenarios/file",
                      json=scenario_body(map="maps/none.txt")).status_code == 404
    assert not (workspace / "scenarios" / "two.toml").exists()
    (workspace / "scenarios" / "bad.toml").write_text("name = 3\n")
    bad = client.get("/api/scenarios/file", params={"path": "scenarios/bad.toml"})
    assert bad.status_code == 422 and "bad.toml" in bad.json()["detail"]


def test_random_placement_keeps_spacing_and_stays_in_the_region(client: TestClient) -> None:
    poses = np.array(client.post("/api/scenarios/place", json={
        "map": "maps/room.txt", "type": "Pioneer2DX", "count": 8, "region": [1, 1, 9, 5],
        "min_spacing": 1.0, "seed": 3, "others": [[5.0, 3.0]]}).json()["poses"])
    assert poses.shape == (8, 3)
    assert ((poses[:, 0] >= 1) & (poses[:, 0] <= 9) & (poses[:, 1] >= 1)
            & (poses[:, 1] <= 5)).all()
    centres = np.vstack([poses[:, :2], [[5.0, 3.0]]])
    gaps = np.hypot(*(centres[:, None] - centres[None]).transpose(2, 0, 1))
    assert gaps[~np.eye(9, dtype=bool)].min() >= 1.0
    crowded = client.post("/api/scenarios/place", json={
        "map": "maps/room.txt", "type": "Pioneer2DX", "count": 50, "region": [1, 1, 2, 2],
        "min_spacing": 1.0})
    assert crowded.status_code == 422 and "cannot place" in crowded.json()["detail"]
    assert client.post("/api/scenarios/place", json={
        "map": "maps/room.txt", "type": "Tank", "count": 1}).status_code == 400


def test_run_records_a_run_folder_that_load_run_reads(client: TestClient, workspace: Path
                                                      ) -> None:
    client.put("/api/scenarios/file", json=scenario_body())
    job = client.post("/api/scenarios/run", json={"path": "scenarios/two.toml",
                                                  "algorithm": "go_to_goal", "seed": 4,
                                                  "time": 1.0}).json()
    done = wait(client, job["id"])
    assert done["state"] == "done", done
    assert done["result"]["run"] == "runs/two-go_to_goal-s4"
    run = load_run(workspace / done["result"]["run"])
    assert run.summary["robots"] == 2 and run.summary["seed"] == 4
    assert run.summary["sim_time"] == 1.0 and done["done"] == done["total"] == 10
    paths = [r["path"] for r in client.get("/api/runs").json()["runs"]]
    assert set(paths) == {"runs/two-go_to_goal-s4", "runs/line-go_to_goal-s1"}
    assert client.post("/api/scenarios/run", json={
        "path": "scenarios/none.toml", "algorithm": "go_to_goal"}).status_code == 404


def test_a_run_whose_step_never_returns_ends_at_its_wall_limit(client: TestClient,
                                                                workspace: Path) -> None:
    client.put("/api/scenarios/file", json=scenario_body())
    (workspace / "algorithms").mkdir(exist_ok=True)
    (workspace / "algorithms" / "stuck.py").write_text(
        "def step(robot):\n    while True:\n        pass\n")
    job = client.post("/api/scenarios/run", json={"path": "scenarios/two.toml",
                                                  "algorithm": "algorithms/stuck.py",
                                                  "wall_limit": 0.5}).json()
    done = wait(client, job["id"])
    assert done["state"] == "done" and done["result"]["status"] == "wall_limit", done
    assert done["result"]["error"].startswith(
        "robot 0: step() did not return within the wall limit of 0.5 s; stopped at step 0")
    assert done["result"]["error"].endswith(("stuck.py:2\n    while True:",
                                             "stuck.py:3\n    pass"))
    run = load_run(workspace / done["result"]["run"])
    assert run.summary["error"] == done["result"]["error"]


def test_frames_carry_the_recorded_poses_and_states(client: TestClient, workspace: Path
                                                    ) -> None:
    path = "runs/line-go_to_goal-s1"
    meta = client.get("/api/runs/meta", params={"path": path}).json()
    body = client.get("/api/runs/frames", params={"path": path}).content
    frames, robots = struct.unpack("<II", body[:8])
    assert (frames, robots) == (meta["frames"], meta["robots"]) == (31, 3)
    times = np.frombuffer(body, "<f4", frames, 8)
    poses = np.frombuffer(body, "<f4", frames * robots * 3, 8 + 4 * frames)
    states = np.frombuffer(body, np.uint8, frames * robots, 8 + 4 * frames * (1 + 3 * robots))
    assert len(body) == 8 + frames * (4 + 12 * robots + robots)
    table = pq.read_table(workspace / path / "trajectory.parquet").to_pandas()
    for step in (0, 17, 30):
        rows = table[table["step"] == step].sort_values("robot")
        assert times[step] == np.float32(rows["time"].iloc[0])
        got = poses.reshape(frames, robots, 3)[step]
        assert np.array_equal(got, rows[["x", "y", "theta"]].to_numpy(np.float32))
        assert states.reshape(frames, robots)[step].tolist() == rows["status"].tolist()
    kind = load_run(workspace / path).scenario.robot_type(0)  # the line's Pioneer3AT
    assert meta["half_length"] == [kind.length / 2] * 3 == [0.35] * 3
    assert meta["beams"] == [kind.ranger.beams] * 3 == [270] * 3


def test_beams_logs_plot_and_video(client: TestClient, workspace: Path) -> None:
    path = "runs/line-go_to_goal-s1"
    beams = client.get("/api/runs/beams", params={"path": path, "robot": 0, "frame": 5}).json()
    assert len(beams["segments"]) == 270
    assert client.get("/api/runs/beams", params={"path": path, "robot": 7,
                                                 "frame": 5}).status_code == 400
    log = client.get("/api/runs/log", params={"path": path, "robot": 1}).json()
    assert log["source"] == "log" and any("go_to_goal" in line for line in log["lines"])
    assert client.get("/api/runs/log", params={"path": path, "robot": 3}).status_code == 400
    plot = client.get("/api/runs/plot", params={"path": path})
    assert plot.content[:8] == b"\x89PNG\r\n\x1a\n"
    assert not list((workspace / path).glob("*.png"))  # a GET writes nothing in the workspace
    assert client.get("/api/runs/video", params={"path": path}).status_code == 404
    job = client.post("/api/runs/export", json={"path": path, "speed": 3.0, "fps": 5}).json()
    done = wait(client, job["id"])
    assert done["state"] == "done" and done["result"]["frames"] == done["total"] == 6
    video = client.get("/api/runs/video", params={"path": path})
    assert video.headers["content-type"] == "video/mp4" and len(video.content) > 1000
    assert client.get("/api/runs/meta", params={"path": path}).json()["video"] is True


def test_a_broken_run_gets_a_message_and_the_server_goes_on(client: TestClient,
                                                            workspace: Path) -> None:
    broken = workspace / "runs" / "broken"
    broken.mkdir()
    (broken / "summary.json").write_text("{not json")
    response = client.get("/api/runs/meta", params={"path": "runs/broken"})
    assert response.status_code == 422 and "summary" in response.json()["detail"]
    listed = {r["path"]: r for r in client.get("/api/runs").json()["runs"]}
    assert "not a readable summary" in listed["runs/broken"]["error"]
    assert client.get("/api/runs/meta", params={"path": "maps"}).status_code == 400
