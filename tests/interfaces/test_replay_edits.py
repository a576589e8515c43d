"""Replays of a run edited as it ran (tests/interfaces/edited_world.py): the walls drawn at
each frame are the walls of its step, the beams end at the walls of its step, a moved
robot's trail breaks at the jump, in the replay's data, its drawing, the video and the
plot; the live view and the notebook's frames redraw the walls as they change."""

from __future__ import annotations

from pathlib import Path as FilePath

import imageio.v2 as imageio
import numpy as np
import pytest
from matplotlib.collections import LineCollection
from matplotlib.path import Path

from mimics.interfaces.live_view import LiveView
from mimics.interfaces.notebook.frames import FrameDrawer
from mimics.interfaces.plots.run_plot import ADDED_WALL_COLOR, plot_run
from mimics.interfaces.render import WALL_COLOR
from mimics.interfaces.replay import BeamCaster, Replayer, export_replay, replay_data
from mimics.interfaces.replay.edits import break_at_moves, wall_timeline
from mimics.records.run_folder import load_run
from mimics.records.runner import prepare
from mimics.world.edits import Edit
from tests.interfaces.edited_world import (
    ADDED_STEP,
    ADDED_WALL,
    GOAL_STEP,
    MOVE_STEP,
    MOVED_ROBOT,
    MOVED_TO,
    NEW_GOAL,
    START_GOALS,
    START_WALL,
    WALLS_BY_STEP,
    beam_ends,
    record_edited_run,
    scenario_file,
    through_added_wall,
    walls_at,
)


@pytest.fixture(scope="module")
def edited_run(tmp_path_factory: pytest.TempPathFactory) -> FilePath:
    return record_edited_run(tmp_path_factory.mktemp("edited") / "run")


def wall_collection(ax) -> LineCollection:
    """The renderer's walls: its one LineCollection at zorder 2."""
    [walls] = [c for c in ax.collections if isinstance(c, LineCollection) and c.zorder == 2]
    return walls


def drawn_walls(ax) -> list[list[float]]:
    return [np.asarray(s, dtype=float).reshape(4).tolist()
            for s in wall_collection(ax).get_segments()]


def jumps_across(path: np.ndarray, limit: float = 1.0) -> int:
    """Consecutive finite points of a polyline more than ``limit`` apart."""
    step = np.hypot(*np.diff(np.asarray(path, dtype=float), axis=0).T)
    return int(np.sum(np.isfinite(step) & (step > limit)))


def drawn_jumps(collection: LineCollection, limit: float = 1.0) -> tuple[list[int], list[int]]:
    """Per line of ``collection``: the pieces Matplotlib draws (a NaN point breaks a line)
    longer than ``limit``, and how many times the line breaks."""
    long, breaks = [], []
    for path in collection.get_paths():
        previous, count, moves = None, 0, 0
        for vertex, code in path.iter_segments(simplify=False):
            if code == Path.LINETO and np.hypot(*(vertex - previous)) > limit:
                count += 1
            moves += code == Path.MOVETO
            previous = vertex
        long.append(count)
        breaks.append(moves - 1)
    return long, breaks


def test_the_replay_holds_the_walls_of_each_step(edited_run: FilePath) -> None:
    data = replay_data(load_run(edited_run))
    assert data.steps.tolist() == list(range(21))
    assert data.walls.steps.tolist() == [first for first, _ in WALLS_BY_STEP]
    assert [w.tolist() for w in data.walls.sets] == [walls for _, walls in WALLS_BY_STEP]
    for k, step in enumerate(data.steps.tolist()):  # the refused rectangle is never drawn
        assert data.walls_at(k).tolist() == walls_at(step)
    assert {robot: steps.tolist() for robot, steps in data.moves.items()} == {
        MOVED_ROBOT: [MOVE_STEP]}
    for k, step in enumerate(data.steps.tolist()):
        goal = NEW_GOAL if step >= GOAL_STEP else START_GOALS[0]
        assert data.goals_at(k).tolist() == [goal, START_GOALS[1]]
    # the moved robot: at its old place in the frame of the edit's step, at the new one next
    assert data.pose[MOVE_STEP, MOVED_ROBOT, 1] == pytest.approx(4.0)
    assert data.pose[MOVE_STEP + 1, MOVED_ROBOT, 1] == pytest.approx(MOVED_TO[1], abs=0.05)


def test_a_run_without_wall_edits_has_one_wall_set() -> None:
    walls = np.array([START_WALL])
    timeline = wall_timeline(walls, [Edit("set_goal", 4, robot=0, x=1.0, y=1.0)])
    assert not timeline.edited and timeline.set_at(np.arange(50)).max() == 0
    at_start = wall_timeline(walls, [Edit("add_wall", 0, segment=tuple(ADDED_WALL))])
    assert at_start.steps.tolist() == [0] and at_start.sets[0].tolist() == [START_WALL,
                                                                             ADDED_WALL]


def test_a_line_breaks_between_the_frames_around_a_move() -> None:
    path = np.array([[0.0, 0.0], [0.1, 0.0], [0.2, 0.0], [5.0, 5.0], [5.1, 5.0]])
    steps = np.array([0, 2, 4, 6, 8])
    broken = break_at_moves(path, steps, np.array([4]))  # moved after step 4
    assert np.isnan(broken[3]).all() and broken[[0, 1, 2, 4, 5]].tolist() == path.tolist()
    assert break_at_moves(path, steps, np.array([5])).shape == (6, 2)  # between 4 and 6
    assert break_at_moves(path, steps, np.array([8, 30])) is path  # after the last frame


def test_beams_end_at_the_walls_of_their_step(edited_run: FilePath) -> None:
    data = replay_data(load_run(edited_run))
    caster = BeamCaster(data.scenario, data.walls.sets)
    for k, step in enumerate(data.steps.tolist()):
        x, y = data.pose[k, 0, :2].astype(float)
        segments = caster.beams(0, data.pose[k], data.status[k], int(data.wall_set[k]))
        direction, ends = beam_ends(segments)
        through = through_added_wall(x, y, direction)
        assert through.sum() > 10
        length = np.hypot(*(ends[through] - (x, y)).T)
        at_wall = (3.0 - x) / np.cos(direction[through])  # the hand-computed distance
        if step >= ADDED_STEP:
            np.testing.assert_allclose(length, at_wall, atol=1e-6)
        elif step < ADDED_STEP:  # the wall at x = 6 (or 8 m of range) is further
            assert (length > at_wall + 2.5).all()
    # one wall index per wall set, each built once
    assert sorted(caster._wall_indexes) == [0, 1, 2]


def test_the_replay_draws_the_walls_trails_and_beams_of_each_frame(edited_run: FilePath) -> None:
    data = replay_data(load_run(edited_run))
    replayer = Replayer.create(data, robot_beams=0, width_px=400)
    for t, step in ((0.0, 0), (0.4, 4), (0.5, 5), (1.1, 11), (1.2, 12), (2.0, 20), (0.9, 9)):
        replayer.show_at(t)
        assert drawn_walls(replayer.renderer.ax) == walls_at(step), t
        goal = NEW_GOAL if step >= GOAL_STEP else START_GOALS[0]
        assert replayer.renderer._goals.get_xydata().tolist() == [goal, START_GOALS[1]], t
    # the moved robot's trail: no line from its old place to its new one
    k = MOVE_STEP + 4
    trails = data.trails(k, 5.0, 16)
    assert np.isnan(trails[MOVED_ROBOT]).any() and jumps_across(trails[MOVED_ROBOT]) == 0
    assert not np.isnan(trails[0]).any()  # the others keep whole trails
    replayer.show_at(float(data.times[k]))
    long, breaks = drawn_jumps(replayer.renderer._trails)
    assert long == [0, 0] and breaks == [0, 1]


def test_the_video_shows_the_added_wall_from_its_step(edited_run: FilePath,
                                                     tmp_path: FilePath) -> None:
    gif = tmp_path / "edited.gif"
    export_replay(edited_run, gif=gif, fps=10, speed=1, width_px=400, progress=False)
    frames = imageio.mimread(gif)
    assert len(frames) == 21  # one per step: 0, 0.1, ..., 2 s
    data = replay_data(load_run(edited_run))
    renderer = Replayer.create(data, width_px=400).renderer
    column, row = renderer.world_to_pixel(np.array([[3.0, 0.5]]))[0].round().astype(int)
    wall_rgb = np.array([int(WALL_COLOR[i:i + 2], 16) for i in (1, 3, 5)])
    seen = [np.abs(frame[row - 3:row + 4, column - 3:column + 4, :3].astype(int)
                   - wall_rgb).sum(axis=2).min() < 40 for frame in frames]
    assert seen == [step >= ADDED_STEP for step in range(21)]


def test_the_plot_marks_added_and_removed_walls_and_breaks_moved_lines(
        edited_run: FilePath) -> None:
    figure = plot_run(edited_run, None)
    ax = figure.axes[0]
    walls = {c.get_label(): [np.asarray(s).reshape(4).tolist() for s in c.get_segments()]
             for c in ax.collections if isinstance(c, LineCollection) and c.zorder == 2}
    assert walls["wall added by an edit"] == [ADDED_WALL]
    assert walls["wall removed by an edit"] == [START_WALL]
    [added] = [c for c in ax.collections if c.get_label() == "wall added by an edit"]
    assert added.get_color()[0][:3].tolist() == pytest.approx(
        [int(ADDED_WALL_COLOR[i:i + 2], 16) / 255 for i in (1, 3, 5)])
    legend = [t.get_text() for t in figure.legends[0].get_texts()]
    assert "wall added by an edit (1)" in legend and "wall removed by an edit (1)" in legend
    assert "goal at the end" in legend
    [crosses] = [line for line in ax.get_lines() if line.get_marker() == "x"]
    assert crosses.get_xydata().tolist() == [NEW_GOAL, START_GOALS[1]]
    [paths] = [c for c in ax.collections if isinstance(c, LineCollection) and c.zorder == 3]
    long, breaks = drawn_jumps(paths)
    assert long == [0, 0] and breaks == [0, 1]  # robot 1 breaks once, robot 0 never


def test_the_live_view_redraws_the_walls_when_an_edit_changes_them(tmp_path: FilePath) -> None:
    sim = prepare(scenario_file(tmp_path), "go_to_goal", seed=1)
    drawn: list[tuple[int, list[list[float]], list[list[float]]]] = []
    view = LiveView("step", offscreen=True, width_px=300, on_frame=lambda t, rgb: drawn.append(
        (sim.state.step, drawn_walls(view.renderer.ax), sim.world_map.segments.tolist())))
    sim.observers.append(view)
    sim.run()
    assert [shown == world for _, shown, world in drawn] == [True] * len(drawn)
    # the engine applies an edit of step s before step s + 1: its frame shows it
    assert [step for step, shown, _ in drawn if shown == [START_WALL, ADDED_WALL]] == list(
        range(ADDED_STEP + 1, 13))


def test_the_notebook_frames_follow_the_edited_walls_and_moves(tmp_path: FilePath) -> None:
    sim = prepare(scenario_file(tmp_path), "go_to_goal", seed=1)
    drawer = FrameDrawer(width_px=300)
    sim.observers.append(drawer)
    sim.start()
    drawer.png(sim)
    assert drawn_walls(drawer.renderer.ax) == [START_WALL]
    for _ in range(MOVE_STEP + 3):
        sim.step()
    assert drawer.png(sim)[:8] == b"\x89PNG\r\n\x1a\n"
    assert drawn_walls(drawer.renderer.ax) == [START_WALL, ADDED_WALL]
    long, _ = drawn_jumps(drawer.renderer._trails)
    assert long == [0, 0]
    sim.edit({"kind": "set_goal", "robot": 0, "x": 2.0, "y": -2.0})
    drawer.png(sim)
    assert drawer.renderer._goals.get_xydata()[0].tolist() == [2.0, -2.0]
