"""The Batteries page's API: count, start, status from SQLite, table, resume, re-run, plots."""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from scipy.stats import wilcoxon

from mimics.batteries.report import runs_table
from mimics.interfaces.web.app import create_app

CRASH = "def step(robot):\n    raise ValueError('on purpose')\n"


def status_when_stopped(client: TestClient, path: str, limit: float = 90.0) -> dict[str, Any]:
    end = time.monotonic() + limit
    while time.monotonic() < end:
        status = client.get("/api/batteries/status", params={"path": path}).json()
        if not status["starting"] and not status["running"] and status["total"]:
            return status
        time.sleep(0.3)
    raise AssertionError(f"{path} still running after {limit} s")


def test_a_battery_runs_from_the_api_and_its_state_comes_from_sqlite(
        client: TestClient, workspace: Path) -> None:
    (workspace / "algorithms" / "crash.py").write_text(CRASH)
    body = {"name": "night", "algorithms": ["go_to_goal", "algorithms/crash.py"],
            "scenarios": [{"name": "line", "params": {"robots": [1, 2]}}], "seeds": 2,
            "time": 0.5}
    assert client.post("/api/batteries", json={**body, "dry_run": True}).json() == {"runs": 8}
    assert not (workspace / "batteries" / "night").exists()
    started = client.post("/api/batteries", json=body).json()
    assert started["runs"] == 8 and started["path"] == "batteries/night"
    status = status_when_stopped(client, "batteries/night")
    assert status["finished"] == status["total"] == 8
    assert status["counts"] == {"done": 4, "error": 4}
    rows = {(r["algorithm"], r["parameters"], r["seed"]): r for r in status["runs"]}
    assert len(rows) == 8
    truth = runs_table(workspace / "batteries" / "night")  # the battery's own report
    for _, row in truth.iterrows():
        mine = rows[(row["algorithm"], row["parameters"], row["seed"])]
        assert mine["state"] == row["state"] and mine["misbehaving"] == bool(row["misbehaving"])
    crashed = [r for r in status["runs"] if r["algorithm"] == "crash"]
    assert all(r["misbehaving"] and r["state"] == "error" for r in crashed)
    assert all((workspace / r["folder"] / "summary.json").is_file() for r in status["runs"])
    assert (workspace / "batteries" / "night.toml").is_file()
    listed = client.get("/api/batteries").json()["batteries"]
    assert listed == [{"path": "batteries/night", "total": 8, "counts": {"done": 4, "error": 4},
                       "running": False}]

    # a new server on the same workspace (a restart) sees the same state, and re-runs failures
    again = TestClient(create_app(workspace, hosts={"testserver"}))
    assert again.get("/api/batteries/status",
                     params={"path": "batteries/night"}).json()["counts"] == status["counts"]
    assert again.post("/api/batteries/rerun-failed",
                      json={"path": "batteries/night"}).status_code == 200
    rerun = status_when_stopped(again, "batteries/night")
    assert {r["attempts"] for r in rerun["runs"] if r["algorithm"] == "crash"} == {2}
    assert {r["attempts"] for r in rerun["runs"] if r["algorithm"] == "go_to_goal"} == {1}
    assert again.post("/api/batteries/resume", json={"path": "batteries/night"}).status_code == 200
    assert status_when_stopped(again, "batteries/night")["finished"] == 8
    for name in ("outcomes.png", "arrivals.png"):
        plot = again.get("/api/batteries/plot", params={"path": "batteries/night",
                                                        "name": name})
        assert plot.content[:4] == b"\x89PNG", name
    assert not (workspace / "batteries" / "night" / "plots").exists()


def test_battery_refusals(client: TestClient, workspace: Path) -> None:
    base = {"name": "b", "algorithms": ["go_to_goal"], "scenarios": [{"name": "line"}]}
    for changes, status in (({"name": "../b"}, 400), ({"name": ""}, 400),
                            ({"policy": "ignore"}, 400),
                            ({"algorithms": ["maps/room.txt"]}, 400),
                            ({"scenarios": [{"name": "maps/room.txt"}]}, 400),
                            ({"scenarios": [{"name": "nowhere"}]}, 404),
                            ({"scenarios": [{"name": "line", "params": {"wheels": 3}}]}, 422),
                            ({"seeds": 0}, 422)):
        response = client.post("/api/batteries", json={**base, **changes, "dry_run": True})
        assert response.status_code == status, (changes, response.json())
    (workspace / "batteries" / "b").mkdir()
    taken = client.post("/api/batteries", json=base)
    assert taken.status_code == 409 and "exists" in taken.json()["detail"]
    for route in ("/api/batteries/resume", "/api/batteries/rerun-failed"):
        assert client.post(route, json={"path": "batteries/b"}).status_code == 400
    assert client.get("/api/batteries/status", params={"path": "runs"}).status_code == 400
    assert client.get("/api/batteries/status", params={"path": "../x"}).status_code == 400
    assert client.get("/api/batteries/plot", params={"path": "batteries/b",
                                                     "name": "x.png"}).status_code == 400


def test_a_battery_between_its_database_and_its_lock_reads_as_running(
        client: TestClient, workspace: Path) -> None:
    """The driver writes battery.db, then takes its lock: a page polling in between must
    keep polling (it stopped at 'stopped; 4 pending' before, and never saw the end)."""
    import threading

    from mimics.batteries.spec import spec_from_dict
    from mimics.batteries.store import BatteryStore

    folder = workspace / "batteries" / "between"
    spec = spec_from_dict({"battery": {"algorithms": ["go_to_goal"], "seeds": 2, "time": 0.5},
                           "scenarios": [{"name": "line", "robots": [1, 2]}]})
    BatteryStore.create(folder, spec).close()  # the database, no lock holder yet
    release = threading.Event()
    jobs = client.app.state.jobs  # type: ignore[attr-defined]
    jobs.start("battery", lambda job: release.wait(30), label="batteries/between")
    try:
        status = client.get("/api/batteries/status", params={"path": "batteries/between"}).json()
        assert status["total"] == 4 and status["finished"] == 0 and not status["starting"]
        assert status["running"]
    finally:
        release.set()
    end = time.monotonic() + 10
    while jobs.running("battery") and time.monotonic() < end:
        time.sleep(0.05)
    status = client.get("/api/batteries/status", params={"path": "batteries/between"}).json()
    assert not status["running"]  # the job ended and nobody holds the lock: stopped


FAULTS = Path(__file__).resolve().parents[2] / "batteries" / "faults"


def test_evidence_of_a_stopping_rule_battery(client: TestClient, workspace: Path) -> None:
    (workspace / "algorithms" / "random_speed.py").write_text(
        (FAULTS / "random_speed.py").read_text())
    (workspace / "algorithms" / "stand_still.py").write_text(
        (FAULTS / "stand_still.py").read_text())
    # path length over 4 s: none standing still (fixed start poses), 1 to 4 m at random speeds
    until = {"metric": "path_length", "half_width": 0.05, "min_seeds": 3, "max_seeds": 6}
    body = {"name": "rule", "algorithms": ["algorithms/stand_still.py",
                                           "algorithms/random_speed.py"],
            "scenarios": [{"name": "line", "params": {"robots": 1, "random_yaw": False}}],
            "time": 4.0, "until": until}
    assert client.post("/api/batteries", json={**body, "dry_run": True}).json() == {
        "runs": 6, "max_runs": 12}
    assert client.post("/api/batteries", json=body).status_code == 200
    status = status_when_stopped(client, "batteries/rule")
    # stand_still never varies: no stop on a sample without spread, so it runs to max_seeds
    assert status["counts"] == {"done": 12}
    found = client.get("/api/batteries/evidence", params={
        "path": "batteries/rule", "metric": ["path_length", "success"]}).json()
    truth = runs_table(workspace / "batteries" / "rule")
    assert found["baseline"] == "stand_still" and found["algorithms"] == ["stand_still",
                                                                          "random_speed"]
    cells = {c["algorithm"]: c for c in found["until"]["cells"]}
    assert cells["stand_still"]["seeds"] == 6 and cells["stand_still"]["state"] == "max seeds"
    assert cells["random_speed"]["seeds"] == 6 and cells["random_speed"]["state"] == "max seeds"
    mine = truth[truth["algorithm"] == "random_speed"]["path_length"]
    row = next(r for r in found["intervals"] if r["algorithm"] == "random_speed")
    assert row["path_length"] == pytest.approx(mine.mean())
    assert row["path_length_n"] == 6
    pair = found["comparison"][0]  # path_length
    assert pair["pairs"] == 6 and pair["baseline"] == "stand_still"
    base = truth[truth["algorithm"] == "stand_still"].set_index("seed")["path_length"]
    other = truth[truth["algorithm"] == "random_speed"].set_index("seed")["path_length"]
    assert pair["mean_difference"] == pytest.approx((other - base).dropna().mean())
    assert pair["p_value"] == pytest.approx(wilcoxon((other - base).dropna()).pvalue)
    assert pair["p_adjusted"] >= pair["p_value"]
    assert [u.split(":")[0] for u in found["unmet"]] == [
        "stand_still x line (robots=1, random_yaw=False)",
        "random_speed x line (robots=1, random_yaw=False)"]
    assert any("stand_still x line" in w for w in found["warnings"])
    swapped = client.get("/api/batteries/evidence", params={
        "path": "batteries/rule", "baseline": "random_speed", "metric": ["success"]}).json()
    assert [r["algorithm"] for r in swapped["comparison"]] == ["stand_still"]
    assert swapped["metrics"] == ["success"]
    bad = client.get("/api/batteries/evidence", params={"path": "batteries/rule",
                                                         "baseline": "nobody"})
    assert bad.status_code == 422 and "--baseline 'nobody'" in bad.json()["detail"]
