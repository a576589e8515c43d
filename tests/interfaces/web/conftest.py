"""Fixtures of the workbench's tests: a workspace, an in-process client, a recorded run."""

from __future__ import annotations

import shutil
import warnings
from pathlib import Path

import pytest

warnings.filterwarnings("ignore", message=".*httpx2.*")  # Starlette's note on its TestClient
from fastapi.testclient import TestClient  # noqa: E402

from mimics.interfaces.web.app import create_app  # noqa: E402
from mimics.records.runner import prepare, run_to_folder  # noqa: E402
from mimics.world.map_files import save_map  # noqa: E402
from mimics.world.maps import Map  # noqa: E402


@pytest.fixture(scope="session")
def recorded_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A finished run of the built-in line scenario: 3 robots, 3 s, per-robot logs on."""
    folder = tmp_path_factory.mktemp("run") / "line-go_to_goal-s1"
    run_to_folder(prepare("line", "go_to_goal", robots=3, time=3.0, seed=1), folder,
                  robot_logs="on")
    return folder


@pytest.fixture
def workspace(tmp_path: Path, recorded_run: Path) -> Path:
    """A workspace with a 10 m x 6 m room (maps/room.txt) and the recorded run in runs/."""
    root = tmp_path / "ws"
    (root / "maps").mkdir(parents=True)
    save_map(Map.box(10.0, 6.0, name="room"), root / "maps" / "room.txt")
    shutil.copytree(recorded_run, root / "runs" / recorded_run.name)
    return root


@pytest.fixture
def client(workspace: Path) -> TestClient:
    """The app on ``workspace``, called in-process (Host ``testserver``)."""
    return TestClient(create_app(workspace, hosts={"testserver"}))
