"""The workbench's guards: paths stay in the workspace, foreign pages cannot change state,
bodies are bounded, uploads of code are off by default, and `mimics ui` warns off loopback."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from mimics.interfaces.cli import main
from mimics.interfaces.web.app import create_app
from mimics.interfaces.web.security import served_hosts

GOOD_MAP = {"path": "maps/a.txt", "name": "a", "bounds": [0, 0, 4, 4],
            "segments": [[0, 0, 4, 0]]}


@pytest.mark.parametrize("path", ["../secret.txt", "maps/../../secret.txt", "/etc/passwd",
                                  "C:/x.txt", ""])
def test_paths_out_of_the_workspace_are_refused_with_400(client: TestClient, path: str
                                                         ) -> None:
    for response in (client.get("/api/maps/file", params={"path": path}),
                     client.get("/api/runs/meta", params={"path": path}),
                     client.get("/api/scenarios/file", params={"path": path}),
                     client.put("/api/maps/file", json={**GOOD_MAP, "path": path})):
        assert response.status_code == 400, (path, response.json())


def test_a_symlink_leading_out_is_refused_with_403_and_nothing_is_read(
        client: TestClient, workspace: Path, tmp_path: Path) -> None:
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "walls.txt").write_text("0 0 1 1\n")
    os.symlink(outside, workspace / "maps" / "link")
    os.symlink(outside / "walls.txt", workspace / "maps" / "file.txt")
    for path in ("maps/link/walls.txt", "maps/file.txt"):
        response = client.get("/api/maps/file", params={"path": path})
        assert response.status_code == 403
        assert "outside the workspace" in response.json()["detail"]
    response = client.put("/api/maps/file", json={**GOOD_MAP, "path": "maps/link/new.txt"})
    assert response.status_code == 403
    assert not (outside / "new.txt").exists()


def test_state_changes_from_another_origin_or_host_are_refused_with_403(
        client: TestClient, workspace: Path) -> None:
    foreign = client.put("/api/maps/file", json=GOOD_MAP,
                         headers={"Origin": "http://evil.example"})
    assert foreign.status_code == 403 and "Origin" in foreign.json()["detail"]
    rebound = client.put("/api/maps/file", json=GOOD_MAP, headers={"Host": "evil.example"})
    assert rebound.status_code == 403 and "Host" in rebound.json()["detail"]
    assert not (workspace / "maps" / "a.txt").exists()
    same = client.put("/api/maps/file", json=GOOD_MAP, headers={"Origin": "http://testserver"})
    assert same.status_code == 200
    # reading is allowed from a page of another origin (the browser keeps it from seeing the
    # answer), but not through a rebound name
    assert client.get("/api/maps", headers={"Origin": "http://evil.example"}).status_code == 200
    for route in ("/", "/api/maps", "/api/runs/frames?path=runs/line-go_to_goal-s1"):
        assert client.get(route, headers={"Host": "evil.example:8765"}).status_code == 403


def test_served_hosts_are_the_bound_address_and_loopback_names() -> None:
    assert served_hosts("127.0.0.1", 8765) == {"127.0.0.1:8765", "localhost:8765",
                                               "::1:8765", "[::1]:8765"}
    assert served_hosts("10.0.0.5", 9000) == {"10.0.0.5:9000"}


def test_bodies_over_the_limit_are_refused_with_413(workspace: Path) -> None:
    client = TestClient(create_app(workspace, hosts={"testserver"}, body_limit=1000,
                                   upload_limit=2000))
    big = {**GOOD_MAP, "segments": [[0, 0, 1, 1]] * 200}
    assert client.put("/api/maps/file", json=big).status_code == 413
    upload = client.post("/api/maps/import", params={"filename": "x.svg"}, content=b"x" * 3000)
    assert upload.status_code == 413
    assert not (workspace / "maps" / "a.txt").exists()


def test_algorithm_uploads_are_off_unless_allowed(client: TestClient, workspace: Path) -> None:
    source = b"def step(robot):\n    return 0.0, 0.0\n"
    refused = client.post("/api/algorithms/upload", params={"filename": "mine.py"},
                          content=source)
    assert refused.status_code == 403 and "--allow-uploads" in refused.json()["detail"]
    assert not (workspace / "algorithms" / "mine.py").exists()
    allowed = TestClient(create_app(workspace, hosts={"testserver"}, allow_uploads=True))
    for bad in ("../mine.py", "mine.txt", ".hidden.py"):
        assert allowed.post("/api/algorithms/upload", params={"filename": bad},
                            content=source).status_code == 400
    done = allowed.post("/api/algorithms/upload", params={"filename": "mine.py"},
                        content=source)
    assert done.json() == {"path": "algorithms/mine.py"}
    assert (workspace / "algorithms" / "mine.py").read_bytes() == source
    assert "algorithms/mine.py" in client.get("/api/algorithms").json()["files"]


def test_only_builtin_or_workspace_algorithm_files_run(client: TestClient, workspace: Path,
                                                       tmp_path: Path) -> None:
    stray = workspace / "maps" / "evil.py"
    stray.write_text("raise SystemExit\n")
    scenario = {"path": "scenarios/s.toml", "map": "maps/room.txt",
                "robots": [{"type": "Pioneer2DX", "x": 1, "y": 1, "goal": [2, 1]}]}
    assert client.put("/api/scenarios/file", json=scenario).status_code == 200
    for algorithm, status in (("maps/evil.py", 400), ("no_such_algorithm", 400),
                              ("../evil.py", 400), ("algorithms/missing.py", 404)):
        response = client.post("/api/scenarios/run", json={"path": "scenarios/s.toml",
                                                           "algorithm": algorithm})
        assert response.status_code == status, algorithm


def test_ui_binds_loopback_by_default_and_warns_otherwise(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import uvicorn

    calls: list[tuple[str, int]] = []
    monkeypatch.setattr(uvicorn, "run", lambda app, host, port, **kw: calls.append((host, port)))
    assert main(["ui", "--workspace", str(tmp_path / "w")]) in (0, None)
    assert calls[-1] == ("127.0.0.1", 8765)
    assert "warning" not in capsys.readouterr().err
    assert main(["ui", "--workspace", str(tmp_path / "w"), "--host", "0.0.0.0", "--port",
                 "9001"]) in (0, None)
    assert calls[-1] == ("0.0.0.0", 9001)
    assert "warning: serving on 0.0.0.0" in capsys.readouterr().err
    assert sorted(p.name for p in (tmp_path / "w").iterdir()) == [
        "algorithms", "batteries", "maps", "runs", "scenarios"]
    (tmp_path / "file").write_text("")
    assert main(["ui", "--workspace", str(tmp_path / "file")]) == 2
    assert "not a folder" in capsys.readouterr().err
