"""The Runs page's API on a run edited as it ran (tests/interfaces/edited_world.py): the
meta gives the wall sets with the frames and steps they start at, and the moves; beams
end at the walls of their frame's step; the page draws the walls of the frame shown
(Playwright, Debian's Chromium)."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from fastapi.testclient import TestClient

from mimics.interfaces.web.app import create_app
from mimics.records.run_folder import load_run
from mimics.world.edits import walls_after
from tests.interfaces.edited_world import (
    ADDED_STEP,
    GOAL_STEP,
    MOVE_STEP,
    MOVED_ROBOT,
    NEW_GOAL,
    START_GOALS,
    WALLS_BY_STEP,
    beam_ends,
    record_edited_run,
    through_added_wall,
)

PATH = "runs/edited"


@pytest.fixture(scope="module")
def edited_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return record_edited_run(tmp_path_factory.mktemp("edited") / "run")


@pytest.fixture
def edited_client(tmp_path: Path, edited_run: Path) -> TestClient:
    shutil.copytree(edited_run, tmp_path / "ws" / PATH)
    return TestClient(create_app(tmp_path / "ws", hosts={"testserver"}))


def test_the_meta_gives_the_wall_sets_and_the_moves(edited_client: TestClient,
                                                    edited_run: Path) -> None:
    meta = edited_client.get("/api/runs/meta", params={"path": PATH}).json()
    assert meta["stride"] == 1 and meta["frames"] == 21  # frame k is step k
    assert [(w["frame"], w["step"], w["segments"]) for w in meta["walls"]] == [
        (first, first, walls) for first, walls in WALLS_BY_STEP]
    scenario = load_run(edited_run).scenario
    applied = [e for e in scenario.edits if e.kind != "add_wall" or e.segment is not None]
    for entry in meta["walls"]:  # what walls_after gives at that step, the refusal left out
        assert entry["segments"] == walls_after(scenario.map.segments, applied,
                                                entry["step"]).tolist()
    assert meta["moves"] == [[MOVED_ROBOT, MOVE_STEP + 1]]  # the first frame at its new place
    assert meta["goals"] == START_GOALS
    assert [(g["frame"], g["step"], g["goals"]) for g in meta["goal_sets"]] == [
        (0, 0, START_GOALS), (GOAL_STEP, GOAL_STEP, [NEW_GOAL, START_GOALS[1]])]


def test_beams_end_at_the_added_wall_from_its_step_on(edited_client: TestClient,
                                                      edited_run: Path) -> None:
    pose = load_run(edited_run).trajectory.set_index(["step", "robot"])
    for frame in (ADDED_STEP - 2, ADDED_STEP - 1, ADDED_STEP, ADDED_STEP + 3, 15):
        x, y = pose.loc[(frame, 0), ["x", "y"]].to_numpy(float)
        answer = edited_client.get("/api/runs/beams",
                                   params={"path": PATH, "robot": 0, "frame": frame}).json()
        direction, ends = beam_ends(np.array(answer["segments"]))
        through = through_added_wall(x, y, direction)
        length = np.hypot(*(ends[through] - (x, y)).T)
        at_wall = (3.0 - x) / np.cos(direction[through])  # by hand: the wall at x = 3
        if frame >= ADDED_STEP:
            np.testing.assert_allclose(length, at_wall, atol=1e-5)
        else:
            assert (length > at_wall + 2.5).all()
        every = edited_client.get("/api/runs/all_beams",
                                  params={"path": PATH, "frame": frame}).json()
        ends_all = np.array(every["segments"]).reshape(-1, 4)[:, 2:]
        on_wall = (np.abs(ends_all[:, 0] - 3.0) < 1e-3) & (np.abs(ends_all[:, 1]) <= 1.0)
        assert on_wall.any() == (frame >= ADDED_STEP)


def test_the_page_draws_the_walls_of_the_frame_shown(page: Any, site: tuple[str, Path],
                                                     edited_run: Path) -> None:
    url, root = site
    shutil.copytree(edited_run, root / PATH)
    page.goto(f"{url}/#/runs?path={PATH}")
    page.wait_for_function("window.workbench.runs.data && window.workbench.runs.meta"
                           " && window.workbench.runs.meta.path === 'runs/edited'")

    def dark_at(frame: int, x: float, y: float, level: int = 80) -> bool:
        """Whether the canvas is darker than ``level`` in every channel (a wall) somewhere
        around world (x, y) with frame ``frame`` shown."""
        return page.evaluate(f"""async () => {{
            const runs = window.workbench.runs;
            runs.seekFrame({frame});
            await new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)));
            const view = runs.view;
            const [px, py] = view.toScreen({x}, {y});
            const ratio = window.devicePixelRatio || 1;
            const data = view.context.getImageData(Math.round(px * ratio) - 2,
                                                   Math.round(py * ratio) - 2, 5, 5).data;
            for (let k = 0; k < data.length; k += 4) {{
                if (Math.max(data[k], data[k + 1], data[k + 2]) < {level}) return true;
            }}
            return false;
        }}""")

    assert not dark_at(ADDED_STEP - 1, 3.0, 0.5) and dark_at(ADDED_STEP, 3.0, 0.5)
    assert dark_at(11, 6.0, -2.0) and not dark_at(12, 6.0, -2.0)  # wall 0 removed at 12
    assert dark_at(2, 6.0, -2.0) and not dark_at(2, 3.0, 0.5)  # back again: the start walls
    # the moved robot's trail (light blue) goes on at y = 4 and starts again at y = 6.5,
    # with no line between the two
    assert dark_at(MOVE_STEP + 6, 0.1, 4.0, 245) and dark_at(MOVE_STEP + 6, 0.05, 6.5, 245)
    assert not dark_at(MOVE_STEP + 6, 0.08, 5.25, 245)
    # robot 0's goal (a grey cross) moves to (8, -2) at the set_goal's frame
    assert not dark_at(GOAL_STEP - 1, *NEW_GOAL, 130) and dark_at(GOAL_STEP, *NEW_GOAL, 130)
