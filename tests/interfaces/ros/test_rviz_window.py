"""The RViz config of ``mimics ros-files`` opens with a 3D view that shows the map.

RViz (Debian's ``rviz``, software GL) runs under a virtual X server against
a real master and a ``mimics ros`` run; the test looks at screenshots
(ImageMagick's ``import``). The truth is RViz's own drawing of the map: with
the ``map`` colour scheme a free cell is white (RViz's map palette gives 255
to occupancy 0), drawn at the display's alpha over the background colour, so
its pixels are ``alpha * 255 + (1 - alpha) * background``: 193 for the config's
0.7 over 48. The same RViz with the old Window Geometry (a size only, no dock
layout: the Displays panel fills the window) is the control: no pixel of that
colour in a large block.
"""

from __future__ import annotations

import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import yaml
from PIL import Image

from mimics.interfaces.ros.launch_files import rviz_config
from tests.system_packages import require

SCREEN = (1280, 800)
OLD_GEOMETRY = "Window Geometry:\n  Height: 800\n  Width: 1200\n"  # the config before
BLOCK = 24  # px: a square of map between the grid's 1 m lines (30 px at the view's scale 30)
PATIENCE = 45.0  # s: how long RViz may take to come up and draw the map on a loaded machine


def free_cell_colour(config: str) -> float:
    """The grey of a free map cell in RViz's view, from the config's alpha and background."""
    data = yaml.safe_load(config)
    manager = data["Visualization Manager"]
    alpha = next(d for d in manager["Displays"] if d["Class"] == "rviz/Map")["Alpha"]
    background = float(manager["Global Options"]["Background Color"].split(";")[0])
    return alpha * 255.0 + (1.0 - alpha) * background


def map_pixels(image: np.ndarray, grey: float) -> np.ndarray:
    """Where the screenshot has that grey (within 2 levels: the GL's rounding)."""
    return np.all(np.abs(image.astype(np.float64) - grey) <= 2.0, axis=2)


def has_block(mask: np.ndarray, size: int) -> bool:
    """Whether ``mask`` holds a ``size`` x ``size`` square of True (an integral image)."""
    total = np.pad(mask.astype(np.int64).cumsum(0).cumsum(1), ((1, 0), (1, 0)))
    squares = (total[size:, size:] - total[:-size, size:] - total[size:, :-size]
               + total[:-size, :-size])
    return bool(np.any(squares == size * size))


def start_display(tmp_path: Path, name: str) -> tuple[subprocess.Popen[bytes], str]:
    """An Xvfb server on a free display number (Xvfb picks it: ``-displayfd``)."""
    read, write = os.pipe()
    server = subprocess.Popen(
        ["Xvfb", "-displayfd", str(write), "-screen", "0", f"{SCREEN[0]}x{SCREEN[1]}x24",
         "-nolisten", "tcp"], pass_fds=(write,), stdout=subprocess.DEVNULL,
        stderr=(tmp_path / f"xvfb_{name}.log").open("w"))
    os.close(write)
    with os.fdopen(read) as stream:
        number = stream.readline().strip()
    if not number:
        server.kill()
        raise RuntimeError(f"Xvfb did not start: {(tmp_path / f'xvfb_{name}.log').read_text()}")
    return server, f":{number}"


def screenshot(display: str, path: Path) -> np.ndarray | None:
    """The whole screen as RGB, or None when ``import`` could not take it yet."""
    done = subprocess.run(["import", "-display", display, "-window", "root", str(path)],
                          capture_output=True, timeout=30, check=False)
    if done.returncode != 0 or not path.exists():
        return None
    with Image.open(path) as image:
        return np.asarray(image.convert("RGB"))


def stop(process: subprocess.Popen[bytes], sig: int = signal.SIGTERM) -> None:
    if process.poll() is None:
        process.send_signal(sig)
    try:
        process.wait(15)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()


def test_rviz_opens_a_3d_view_showing_the_map(ros_env: dict[str, str], tmp_path: Path) -> None:
    require("rviz")
    new = rviz_config(2, "stage")
    old = re.sub(r"(?ms)^Window Geometry:.*\Z", OLD_GEOMETRY, new)
    assert "QMainWindow State" in yaml.safe_load(new)["Window Geometry"]
    assert yaml.safe_load(old)["Window Geometry"] == {"Height": 800, "Width": 1200}
    grey = free_cell_colour(new)
    assert round(grey) == 193  # 0.7 * 255 + 0.3 * 48
    env = {**ros_env, "HOME": str(tmp_path)}  # RViz keeps its settings under ~/.rviz
    processes: list[subprocess.Popen[bytes]] = []
    try:
        processes.append(subprocess.Popen(
            [sys.executable, "-m", "mimics", "ros", "line", "--robots", "2", "--names",
             "stage", "--time", "600", "--out", str(tmp_path / "run"), "--robot-logs", "off"],
            env=env, stdout=subprocess.DEVNULL, stderr=(tmp_path / "ros.log").open("w")))
        shots: dict[str, np.ndarray | None] = {}
        displays = {}
        for name, config in (("new", new), ("old", old)):
            (tmp_path / f"{name}.rviz").write_text(config)
            server, display = start_display(tmp_path, name)
            processes.append(server)
            displays[name] = display
            processes.append(subprocess.Popen(
                ["rviz", "-d", str(tmp_path / f"{name}.rviz")], env={**env, "DISPLAY": display},
                stdout=subprocess.DEVNULL, stderr=(tmp_path / f"rviz_{name}.log").open("w")))
        deadline = time.monotonic() + PATIENCE
        while time.monotonic() < deadline:
            time.sleep(1.0)
            shots = {name: screenshot(display, tmp_path / f"{name}.png")
                     for name, display in displays.items()}
            new_shot, old_shot = shots["new"], shots["old"]
            # the old window is up once its Displays panel (white) covers much of the screen
            old_up = old_shot is not None and np.mean(np.all(old_shot == 255, axis=2)) > 0.3
            if old_up and new_shot is not None and has_block(map_pixels(new_shot, grey), BLOCK):
                break
        for process in processes[1:]:
            assert process.poll() is None, f"{process.args[0]} ended early: see {tmp_path}"
    finally:
        for process in reversed(processes):
            stop(process, signal.SIGINT if process is processes[0] else signal.SIGTERM)
    new_shot, old_shot = shots.get("new"), shots.get("old")
    assert new_shot is not None and old_shot is not None, f"no screenshot: see {tmp_path}"
    assert new_shot.shape[:2] == (SCREEN[1], SCREEN[0])
    found = map_pixels(new_shot, grey)
    # the line scenario's map, 30 px a metre, fills a large part of the 3D view
    assert has_block(found, BLOCK) and found.mean() > 0.1, f"no map drawn: see {tmp_path}"
    assert np.mean(np.all(old_shot == 255, axis=2)) > 0.3  # the old window did come up...
    assert not has_block(map_pixels(old_shot, grey), BLOCK)  # ...with no 3D view in it
