"""mimics.show's live view in a real JupyterLab (from PyPI), driven by Playwright in
Debian's Chromium: the picture changes while the run plays and freezes when paused.

JupyterLab is served on loopback with a token, from a temporary folder, with its
own configuration folders (nothing of the machine's is read or written).
"""

from __future__ import annotations

import io
import json
import os
import secrets
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import imageio.v3 as imageio
import numpy as np
import pytest

from tests.local_servers import stop_process

CELL = """import mimics
view = mimics.show("circle_swap", "wall_aware", robots=6, time=600, speed=1)
view"""


@pytest.fixture(scope="module")
def lab(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, str, Path]]:
    """A JupyterLab server: its URL, token and root folder."""
    root = tmp_path_factory.mktemp("lab")
    (root / "work").mkdir()
    notebook = {"cells": [{"cell_type": "code", "execution_count": None, "id": "live",
                           "metadata": {}, "outputs": [], "source": CELL}],
                "metadata": {"kernelspec": {"display_name": "Python 3", "language": "python",
                                            "name": "python3"}},
                "nbformat": 4, "nbformat_minor": 5}
    (root / "work" / "live.ipynb").write_text(json.dumps(notebook))
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        port = probe.getsockname()[1]
    token = secrets.token_hex(16)
    env = {**os.environ,
           "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}",
           "JUPYTER_CONFIG_DIR": str(root / "config"), "JUPYTER_RUNTIME_DIR": str(root / "rt"),
           "JUPYTERLAB_SETTINGS_DIR": str(root / "settings"),
           "JUPYTERLAB_WORKSPACES_DIR": str(root / "workspaces"), "IPYTHONDIR": str(root / "ip")}
    log = (root / "lab.log").open("w")
    server = subprocess.Popen(
        [sys.executable, "-m", "jupyterlab", "--no-browser", "--allow-root",
         "--ServerApp.ip=127.0.0.1",
         f"--ServerApp.port={port}", "--ServerApp.port_retries=0",
         f"--IdentityProvider.token={token}", f"--ServerApp.root_dir={root / 'work'}",
         "--LabApp.news_url=", "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate"],
        env=env, stdout=log, stderr=subprocess.STDOUT)
    url = f"http://127.0.0.1:{port}"
    deadline = time.monotonic() + 120
    while True:
        try:
            with urllib.request.urlopen(f"{url}/api/status?token={token}", timeout=2):
                break
        except OSError:
            if server.poll() is not None or time.monotonic() > deadline:
                log.close()
                raise RuntimeError("JupyterLab did not start:\n"
                                   + (root / "lab.log").read_text()[-3000:]) from None
            time.sleep(0.3)
    yield url, token, root
    stop_process(server, grace=20)
    log.close()


def picture(frame: Any) -> np.ndarray:
    """The widget's image as pixels (a screenshot of the element)."""
    return imageio.imread(io.BytesIO(frame.screenshot()))


def test_live_view_changes_while_playing_and_freezes_when_paused(lab, browser, tmp_path):
    url, token, _root = lab
    page = browser.new_page(viewport={"width": 1400, "height": 1000})
    errors: list[str] = []
    page.on("pageerror", lambda e: errors.append(str(e)))
    try:
        page.goto(f"{url}/lab/tree/live.ipynb?token={token}", timeout=120_000)
        editor = page.locator(".jp-Notebook .jp-Cell .cm-content").first
        editor.wait_for(timeout=120_000)
        # the kernel connected and idle, then the cell runs (Shift+Enter)
        page.get_by_text("Python 3 (ipykernel) | Idle").wait_for(timeout=120_000)
        editor.click()
        page.keyboard.press("Shift+Enter")
        frame = page.locator("img.mimics-frame")
        frame.wait_for(timeout=240_000)
        page.wait_for_function(
            "() => { const i = document.querySelector('img.mimics-frame');"
            " return i && i.complete && i.naturalWidth > 0 && Number(i.dataset.frames) > 3; }",
            timeout=240_000)
        # playing: two pictures a second apart differ (the robots and the clock moved)
        first = picture(frame)
        page.wait_for_timeout(1500)
        second = picture(frame)
        assert first.shape == second.shape and not np.array_equal(first, second)
        # paused: the picture stays as it is
        page.locator("button.mimics-pause").click()
        page.wait_for_selector(".mimics-live[data-state='paused']", timeout=30_000)
        page.wait_for_timeout(500)  # the frame in flight, if any, arrives
        paused = picture(frame)
        page.wait_for_timeout(2000)
        assert np.array_equal(paused, picture(frame))
        # one step: a new picture, then still again
        before = page.locator(".mimics-info").inner_text()
        page.locator("button.mimics-step").click()
        page.wait_for_function(  # the clock moved by one step (0.1 s)
            "(before) => document.querySelector('.mimics-info').textContent !== before",
            arg=before, timeout=60_000)
        page.wait_for_timeout(500)
        stepped = picture(frame)
        assert not np.array_equal(paused, stepped)
        # stop: the run ends, the buttons say so
        page.locator("button.mimics-stop").click()
        page.wait_for_selector(".mimics-live[data-state='ended']", timeout=30_000)
        assert page.locator("button.mimics-play").is_disabled()
        assert "ended: stopped" in page.locator(".mimics-info").inner_text()
        assert not [e for e in errors if "mimics" in e], errors
    finally:
        print("page errors:", errors)
        page.screenshot(path=str(tmp_path / "jupyterlab.png"))
        print(f"screenshot: {tmp_path / 'jupyterlab.png'}")
        page.close()
