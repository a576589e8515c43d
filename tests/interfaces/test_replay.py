"""Replays: dense arrays from a run's trajectory, video/GIF export, the window, bad input."""

import shutil
from pathlib import Path
from types import SimpleNamespace

import imageio.v2 as imageio
import numpy as np
import pandas as pd
import pytest
import typer
from typer.testing import CliRunner

from mimics.engine.state import Status
from mimics.interfaces.cli.view import replay_command
from mimics.interfaces.render import figure_size
from mimics.interfaces.replay import (
    Replayer,
    ReplayWindow,
    export_replay,
    frame_times,
    replay_data,
)
from mimics.records.run_folder import load_run
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


def write_run_folder(folder: Path, run: SimpleNamespace) -> Path:
    """Write a synthetic run as a run folder that ``mimics.load_run`` reads."""
    import json

    import pyarrow as pa
    import pyarrow.parquet as pq

    from mimics.records.events import EVENTS_SCHEMA
    from mimics.records.scenario_record import write_scenario_record
    from mimics.records.trajectory import TRAJECTORY_SCHEMA

    folder.mkdir(parents=True)
    write_scenario_record(folder / "scenario.toml", run.scenario,
                          {"seed": 7, "algorithm": "scripted"})
    traj = run.trajectory
    columns = {name: traj[name] if name in traj else np.zeros(len(traj))
               for name in TRAJECTORY_SCHEMA.names}
    pq.write_table(pa.Table.from_pydict(columns, schema=TRAJECTORY_SCHEMA),
                   folder / "trajectory.parquet")
    events = run.events.assign(step=(run.events["time"] / DT).round().astype(int),
                               start=np.nan, traceback="")
    pq.write_table(pa.Table.from_pandas(events[EVENTS_SCHEMA.names], schema=EVENTS_SCHEMA,
                                        preserve_index=False), folder / "events.parquet")
    (folder / "summary.json").write_text(json.dumps({**run.summary, "robots": 3}))
    return folder


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return write_run_folder(tmp_path_factory.mktemp("replay") / "run", synthetic_run())


def cli() -> typer.Typer:
    app = typer.Typer()
    app.command("replay")(replay_command)
    app.command("other")(lambda: None)  # two commands: "replay" stays a subcommand
    return app


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


def test_video_has_the_expected_frames_size_and_pixels(run_folder: Path,
                                                      tmp_path: Path) -> None:
    run = load_run(run_folder)
    out = tmp_path / "run.mp4"
    result = export_replay(run_folder, video=out, fps=10, speed=1, progress=False)
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


def test_the_cli_exports_a_gif_at_a_higher_speed(run_folder: Path, tmp_path: Path) -> None:
    out = tmp_path / "run.gif"
    result = CliRunner().invoke(cli(), ["replay", str(run_folder), "--gif", str(out),
                                        "--speed", "4", "--no-progress"])
    assert result.exit_code == 0, result.output
    assert "14 frames" in result.stdout
    frames = imageio.mimread(out)
    assert len(frames) == 14
    assert frames[0].shape[:2] == figure_size((0.0, 0.0, 10.0, 6.0))[1::-1]


def test_bad_run_folders_are_one_line_errors(run_folder: Path, tmp_path: Path) -> None:
    broken = tmp_path / "broken"
    shutil.copytree(run_folder, broken)
    data = (broken / "trajectory.parquet").read_bytes()
    (broken / "trajectory.parquet").write_bytes(data[: len(data) // 2])
    with pytest.raises(MimicsError, match=r"trajectory\.parquet"):
        export_replay(broken, video=tmp_path / "a.mp4", progress=False)
    assert not (tmp_path / "a.mp4").exists()  # nothing half-written is left
    for folder, words in ((broken, "trajectory.parquet"), (tmp_path, "not a run folder"),
                          (tmp_path / "missing", "not a run folder")):
        result = CliRunner().invoke(cli(), ["replay", str(folder), "--video",
                                            str(tmp_path / "b.mp4"), "--no-progress"])
        assert result.exit_code == 2
        lines = result.stderr.strip().splitlines()
        assert len(lines) == 1 and lines[0].startswith("mimics: error: ") and words in lines[0]
    result = CliRunner().invoke(cli(), ["replay", str(run_folder)])  # a window: no display
    assert result.exit_code == 2 and "--video" in result.stderr


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
