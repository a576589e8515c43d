"""Replays: dense arrays from a run's trajectory, video/GIF export, the window, bad input."""

from pathlib import Path
from types import SimpleNamespace

import imageio.v2 as imageio
import numpy as np
import pandas as pd
import pytest

from mimics.engine.state import Status
from mimics.interfaces.replay import (
    Replayer,
    ReplayWindow,
    export_replay,
    frame_times,
    replay_data,
)
from mimics.world.errors import MimicsError
from mimics.world.maps import Map
from mimics.world.robot_types import RobotType
from mimics.world.scenario import Scenario, Settings

BIG = RobotType("big", width=1.0, length=1.6, kv=1.0, kw=1.0, tau_v=0.5, tau_w=0.2)
DT = 0.1
DURATION = 5.0
STARTS = [[1.0, 1.5, 0.0, 0.0, 9.0, 1.5], [1.0, 4.5, 0.0, 0.0, 9.0, 4.5],
          [5.0, 3.0, np.pi / 2, 0.0, np.nan, np.nan]]


def logged_pose(robot: int, t: float) -> tuple[float, float, float, int]:
    """The scripted run: robots 0 and 1 drive at 1.2 m/s until 3 s and 4 s, robot 2 waits."""
    x0, y0, theta = STARTS[robot][:3]
    if robot == 2:
        return x0, y0, theta, Status.ACTIVE
    stop = 3.0 + robot
    status = Status.ACTIVE if t < stop - 1e-9 else (Status.REACHED_GOAL if robot == 0
                                                    else Status.COLLIDED)
    return x0 + 1.2 * min(t, stop), y0, theta, status


def synthetic_run(drop_after_stop: bool = False) -> SimpleNamespace:
    """A known run: 3 big robots in a 10 x 6 m box, logged every step for 5 s."""
    scenario = Scenario.from_matrix(STARTS, Map.box(10.0, 6.0), BIG,
                                    settings=Settings(dt=DT, time_limit=DURATION),
                                    name="synthetic")
    rows = []
    for k in range(round(DURATION / DT) + 1):
        t = k * DT
        for robot in range(3):
            x, y, theta, status = logged_pose(robot, t)
            if drop_after_stop and robot == 1 and t > 4.0 - 1e-9:
                continue  # a writer that stops logging a robot once it is deactivated
            rows.append({"time": t, "step": k, "robot": robot, "x": x, "y": y, "theta": theta,
                         "status": int(status)})
    events = pd.DataFrame([
        {"time": 3.0, "robot": 0, "kind": "reached_goal", "detail": "Reached goal", "other": -2},
        {"time": 2.0, "robot": 2, "kind": "livelock", "detail": "Livelock", "other": -2},
        {"time": 4.0, "robot": 1, "kind": "collision", "detail": "Collision with wall",
         "other": -1}])
    return SimpleNamespace(summary={"scenario": "synthetic", "algorithm": "scripted",
                                    "seed": 7, "status": "time_limit"},
                           trajectory=pd.DataFrame(rows), events=events, scenario=scenario)


def close(actual: np.ndarray, expected: tuple[int, int, int], tol: int = 24) -> bool:
    return bool(np.all(np.abs(actual.astype(int) - np.array(expected)) <= tol))


def test_frame_times_cover_the_run_and_end_on_its_last_state() -> None:
    np.testing.assert_allclose(frame_times(5.0, fps=10, speed=1), np.arange(51) * 0.1)
    np.testing.assert_allclose(frame_times(5.0, fps=10, speed=4), [0, 0.4, 0.8, 1.2, 1.6, 2.0,
                                                                   2.4, 2.8, 3.2, 3.6, 4.0,
                                                                   4.4, 4.8, 5.0])
    assert len(frame_times(60.0, fps=10, speed=1)) == 601
    with pytest.raises(MimicsError):
        frame_times(1.0, fps=0, speed=1)


def test_replay_data_holds_the_logged_states() -> None:
    data = replay_data(synthetic_run())
    assert data.pose.shape == (51, 3, 3) and data.duration == pytest.approx(5.0)
    k = data.index_at(2.5)
    assert data.times[k] == pytest.approx(2.5)
    np.testing.assert_allclose(data.pose[k, 0], logged_pose(0, 2.5)[:3], atol=1e-5)
    assert data.status[data.index_at(4.5)].tolist() == [Status.REACHED_GOAL, Status.COLLIDED,
                                                        Status.ACTIVE]
    assert not data.livelock[data.index_at(1.9), 2] and data.livelock[data.index_at(2.0), 2]
    assert data.title == "synthetic / scripted / seed 7"


def test_a_robot_no_longer_logged_keeps_its_last_pose_and_its_final_state() -> None:
    data = replay_data(synthetic_run(drop_after_stop=True))
    k = data.index_at(5.0)
    np.testing.assert_allclose(data.pose[k, 1, :2], [1.0 + 1.2 * 3.9, 4.5], atol=1e-5)
    assert data.status[k, 1] == Status.COLLIDED  # from the collision event at 4 s


def test_video_has_the_expected_frames_size_and_pixels(tmp_path: Path) -> None:
    run = synthetic_run()
    out = tmp_path / "run.mp4"
    result = export_replay(run, video=out, fps=10, speed=1, progress=False)
    assert result.frames == 51
    reader = imageio.get_reader(out, format="FFMPEG")
    frames = [frame for frame in reader]
    assert len(frames) == 51
    assert frames[0].shape == (result.height, result.width, 3)
    # Locate the robots with the same layout the export used.
    renderer = Replayer.create(replay_data(run)).renderer
    assert renderer.figure.canvas.get_width_height() == (result.width, result.height)
    t = 2.5
    frame = frames[25]
    for robot, name in ((0, "active"), (2, "livelock")):
        col, row = renderer.world_to_pixel(np.array([logged_pose(robot, t)[:2]]))[0]
        assert close(frame[int(row), int(col)], renderer.color_of(name)), (robot, name)
    col, row = renderer.world_to_pixel(np.array([[8.5, 3.0]]))[0]  # far from every robot
    assert close(frame[int(row), int(col)], (255, 255, 255), tol=8)
    # After their stops, robots 0 and 1 show their final states.
    last = frames[-1]
    for robot, name in ((0, "reached_goal"), (1, "collided")):
        col, row = renderer.world_to_pixel(np.array([logged_pose(robot, 5.0)[:2]]))[0]
        assert close(last[int(row), int(col)], renderer.color_of(name)), (robot, name)


def test_gif_export_at_a_higher_speed(tmp_path: Path) -> None:
    out = tmp_path / "run.gif"
    result = export_replay(synthetic_run(), gif=out, fps=10, speed=4, progress=False)
    frames = imageio.mimread(out)
    assert len(frames) == result.frames == 14
    assert frames[0].shape[:2] == (result.height, result.width)


def test_unwritable_outputs_and_bad_arguments_are_one_line_errors(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    with pytest.raises(MimicsError, match="cannot write"):
        export_replay(synthetic_run(), video=blocker / "out.mp4", progress=False)
    with pytest.raises(MimicsError, match=r"\.mp4"):
        export_replay(synthetic_run(), video=tmp_path / "out.txt", progress=False)
    with pytest.raises(MimicsError, match="--video"):
        export_replay(synthetic_run(), progress=False)
    with pytest.raises(MimicsError, match="beams"):
        export_replay(synthetic_run(), gif=tmp_path / "a.gif", robot_beams=9, progress=False)


def test_missing_columns_and_unknown_robots_are_reported() -> None:
    run = synthetic_run()
    run.trajectory = run.trajectory.drop(columns=["theta"])
    with pytest.raises(MimicsError, match="theta"):
        replay_data(run)
    run = synthetic_run()
    run.trajectory.loc[0, "robot"] = 12
    with pytest.raises(MimicsError, match="robot 12"):
        replay_data(run)


def test_the_window_plays_seeks_and_pauses_at_the_end() -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure()
    FigureCanvasAgg(figure)
    window = ReplayWindow(replay_data(synthetic_run()), fps=10, speed=2, figure=figure)
    assert window.speed == 2
    window.seek(1.0)
    assert window.time == pytest.approx(1.0)
    window.toggle()
    assert window.playing
    window.tick()
    assert window.time == pytest.approx(1.2)
    window.seek(4.9)
    window.tick()
    assert window.time == pytest.approx(5.0) and not window.playing
    window.seek(-3)
    assert window.time == 0.0


def test_beams_are_recomputed_against_walls_and_other_robots() -> None:
    from mimics.interfaces.replay import BeamCaster
    from mimics.world.robot_types import RangerSpec

    seeing = RobotType("seeing", width=1.0, length=1.6, kv=1.0, kw=1.0, tau_v=0.5, tau_w=0.2,
                       ranger=RangerSpec("test", fov=np.pi, beams=3, range=20.0))
    scenario = Scenario.from_matrix([[2.0, 3.0, 0.0, 0.0], [6.0, 3.0, 0.0, 0.0]],
                                    Map.box(10.0, 6.0), seeing)
    caster = BeamCaster(scenario)
    pose = np.array([[2.0, 3.0, 0.0], [6.0, 3.0, 0.0]])
    active = np.zeros(2, dtype=np.int8)
    beams = caster.beams(0, pose, active)
    lengths = np.hypot(*(beams[:, 1] - beams[:, 0]).T)
    # Right beam to the bottom wall, forward beam to robot 1's rear edge, left to the top wall.
    np.testing.assert_allclose(lengths, [3.0, 6.0 - 0.8 - 2.0, 3.0], atol=1e-9)
    escaped = np.array([Status.ACTIVE, Status.ESCAPED], dtype=np.int8)
    assert np.hypot(*(caster.beams(0, pose, escaped)[1, 1] - pose[0, :2])) == pytest.approx(8.0)
    assert caster.beams(1, pose, escaped) is None
