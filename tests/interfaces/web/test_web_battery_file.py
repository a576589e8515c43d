"""A battery file written by the page holds no absolute path: scenario and algorithm files
are named relative to ``batteries/``, where the file lies, so that ``mimics battery run``
reads it from any working folder and the workspace can be moved."""

from __future__ import annotations

import shutil
import tomllib
from pathlib import Path

from fastapi.testclient import TestClient

from mimics.batteries.spec import load_battery
from tests.interfaces.web.test_web_api import scenario_body
from tests.interfaces.web.test_web_batteries import status_when_stopped


def test_the_battery_file_names_workspace_files_relative_to_itself(
        client: TestClient, workspace: Path, tmp_path: Path) -> None:
    assert client.put("/api/scenarios/file", json=scenario_body()).status_code == 200
    (workspace / "algorithms").mkdir(exist_ok=True)
    (workspace / "algorithms" / "mine.py").write_text("def step(robot):\n    return 0.1, 0.0\n")
    body = {"name": "rel", "algorithms": ["go_to_goal", "algorithms/mine.py"],
            "scenarios": [{"name": "scenarios/two.toml"}, {"name": "line"}], "seeds": 1,
            "time": 0.2}
    started = client.post("/api/batteries", json=body)
    assert started.status_code == 200, started.text
    assert started.json()["runs"] == 4
    written = (workspace / "batteries" / "rel.toml").read_text()
    assert str(workspace) not in written
    data = tomllib.loads(written)
    assert data["battery"]["algorithms"] == ["go_to_goal", "../algorithms/mine.py"]
    assert [s["name"] for s in data["scenarios"]] == ["../scenarios/two.toml", "line"]
    status = status_when_stopped(client, "batteries/rel")
    assert status["counts"] == {"done": 4}
    moved = tmp_path / "elsewhere"  # the whole workspace moved: its battery file still reads
    shutil.copytree(workspace / "scenarios", moved / "scenarios")
    shutil.copytree(workspace / "algorithms", moved / "algorithms")
    shutil.copytree(workspace / "maps", moved / "maps")
    (moved / "batteries").mkdir()
    shutil.copy(workspace / "batteries" / "rel.toml", moved / "batteries" / "rel.toml")
    spec = load_battery(moved / "batteries" / "rel.toml")
    assert len(spec.runs()) == 4
