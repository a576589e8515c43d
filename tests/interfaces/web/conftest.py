"""Fixtures of the workbench's tests: a workspace, an in-process client, a recorded run;
for the browser tests, the served workbench, Chromium and a page."""

from __future__ import annotations

import shutil
import socket
import threading
import time
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
import uvicorn

warnings.filterwarnings("ignore", message=".*httpx2.*")  # Starlette's note on its TestClient
from fastapi.testclient import TestClient  # noqa: E402

from mimics.interfaces.web.app import create_app  # noqa: E402
from mimics.records.runner import prepare, run_to_folder  # noqa: E402
from mimics.world.map_files import save_map  # noqa: E402
from mimics.world.maps import Map  # noqa: E402
from tests.interfaces.web.browser import screenshot  # noqa: E402


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


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory, recorded_run: Path
         ) -> Iterator[tuple[str, Path]]:
    """The workbench serving a fresh workspace (with a recorded run): its URL and folder."""
    root = tmp_path_factory.mktemp("e2e") / "ws"
    (root / "runs").mkdir(parents=True)
    shutil.copytree(recorded_run, root / "runs" / recorded_run.name)
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    server = uvicorn.Server(uvicorn.Config(create_app(root, port=port), host="127.0.0.1",
                                           port=port, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    while not server.started:
        time.sleep(0.02)
    yield f"http://127.0.0.1:{port}", root
    server.should_exit = True
    thread.join(10)


@pytest.fixture
def page(browser: Any, site: tuple[str, Path], tmp_path_factory: pytest.TempPathFactory,
         request: pytest.FixtureRequest) -> Iterator[Any]:
    """A fresh page; after the test: no console errors, and a screenshot kept."""
    tab = browser.new_page(viewport={"width": 1280, "height": 800})
    errors: list[str] = []
    tab.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
    tab.on("pageerror", lambda e: errors.append(str(e)))
    tab.console_errors = errors  # a test may take out the refusals it caused on purpose
    yield tab
    screenshot(tab, tmp_path_factory, request.node.name)
    tab.close()
    assert errors == [], errors
