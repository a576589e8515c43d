"""The API's messages are written for the page: no command-line advice, no line of a file
that was never written, no server path, no pydantic wording."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from fastapi.testclient import TestClient

BASE = {"path": "scenarios/a.toml", "name": "a", "map": "maps/room.txt"}


def refused(client: TestClient, **body: Any) -> str:
    response = client.put("/api/scenarios/file", json={**BASE, **body})
    assert response.status_code == 422, response.text
    detail = response.json()["detail"]
    assert isinstance(detail, str)
    return detail


def robot(x: float, y: float, type_: str = "Pioneer2DX") -> dict[str, Any]:
    return {"type": type_, "x": x, "y": y}


def test_scenario_problems_name_robots_not_lines_and_give_no_cli_advice(
        client: TestClient, workspace: Path) -> None:
    assert refused(client, robots=[robot(0.1, 1.0)]) == (
        "robot 0: robot at (0.1, 1) touches wall 3 (0, 6)-(0, 0) at the start "
        "(expected it in free space)")
    assert refused(client, robots=[robot(5, 1), robot(3, 1), robot(3.1, 1), robot(30, 1)]) == (
        "robot 3: start (30, 1) is outside the map bounds (0, 0, 10, 6); robot 1 at (3, 1) and "
        "robot 2 at (3.1, 1) overlap at the start (expected them apart) (2 start problems)")
    assert refused(client, robots=[robot(3, 1, "Nope")]) == (
        "robot 0's type: unknown robot type 'Nope' (expected one of Pioneer3AT, Pioneer2DX, "
        "Swarmbot, TurtleBot3Burger, e-puck, Kobuki, point)")
    assert refused(client, robots=[robot(3, 1, "Pioneer2DX_b-3_r8_n0")], types={
        "Pioneer2DX_b-3_r8_n0": {"base": "Pioneer2DX", "ranger": {"beams": -3}}}) == (
        "sensors of Pioneer2DX: beams: expected a whole number from 0 to 100000, got -3")
    assert refused(client, robots=[robot(3, 1)], settings={"time_limit": -1}) == (
        "time limit: expected a positive number (finite), got -1.0")
    assert refused(client, robots=[]) == (
        "a scenario needs at least one robot: place robots on the map first")
    assert not (workspace / "scenarios" / "a.toml").exists()


def test_no_server_path_in_messages(client: TestClient, workspace: Path) -> None:
    broken = client.post("/api/maps/import", params={"filename": "plan.svg"},
                         content=b"<svg><nope")
    assert broken.status_code == 422
    assert broken.json()["detail"] == ("plan.svg: not a valid SVG (XML error: unclosed token: "
                                       "line 1, column 5)")
    (workspace / "scenarios").mkdir(exist_ok=True)
    (workspace / "scenarios" / "bad.toml").write_text("name = 3\n")
    opened = client.get("/api/scenarios/file", params={"path": "scenarios/bad.toml"})
    assert opened.status_code == 422
    assert opened.json()["detail"].startswith("scenarios/bad.toml")
    assert str(workspace) not in opened.json()["detail"]
    short = client.put("/api/maps/file", json={"path": "maps/x.txt", "bounds": [0, 0, 1]})
    assert short.json()["detail"] == "map bounds: expected at least 4 values, got 3"
