"""mimics.simulate's RunView: recorded in memory, the same rows as a run folder, and
the figure and replay of the commands.

The folder written by the RunRecorder is the independent truth for the memory
recording; the PNG of ``mimics plot`` for ``.plot()``; frames decoded from the
video (imageio) and counted by hand for ``.animate()``.
"""

from __future__ import annotations

import base64
import io
import math
import re
from pathlib import Path

import imageio.v3 as imageio
import numpy as np
import pandas as pd
import pytest
from matplotlib.figure import Figure

import mimics
from mimics.interfaces.cli import main
from mimics.interfaces.notebook.html import png_bytes
from mimics.records.runner import prepare, run_to_folder
from mimics.world.errors import MimicsError

# user_time is the wall time of the user code: the only column that differs between runs
TIMED = ["user_time"]


@pytest.fixture(scope="module")
def memory_run() -> mimics.RunView:
    return mimics.simulate("circle_swap", "wall_aware", robots=4, time=3.0, seed=2)


def test_memory_recording_has_the_rows_and_events_of_a_run_folder(memory_run, tmp_path):
    folder_result = run_to_folder(prepare("circle_swap", "wall_aware", robots=4, time=3.0,
                                          seed=2), tmp_path, robot_logs="off")
    on_disk = mimics.load_run(tmp_path)
    assert memory_run.path is None and not any(Path.cwd().glob("trajectory.parquet"))
    pd.testing.assert_frame_equal(memory_run.trajectory.drop(columns=TIMED),
                                  on_disk.trajectory.drop(columns=TIMED))
    pd.testing.assert_frame_equal(memory_run.events, on_disk.events)
    assert list(memory_run.trajectory.columns) == list(on_disk.trajectory.columns)
    # 4 robots, none deactivated in 3 s: one row per robot per step, 0..30
    assert len(memory_run.trajectory) == 4 * 31
    assert memory_run.summary()["steps"] == folder_result.steps == 30


def test_old_callers_keep_their_attributes(memory_run):
    summary = memory_run.summary()
    assert isinstance(summary, dict) and summary == dict(memory_run.summary)
    assert memory_run.summary["robots"] == 4 == memory_run.robots
    assert memory_run.status == "time_limit" == summary["status"]
    assert memory_run.reached_goal == summary["reached_goal"] == 0
    assert memory_run.final_status.shape == (4,)  # the engine's RunResult, through the view
    assert memory_run.robot(1)["step"].tolist() == list(range(31))
    with pytest.raises(AttributeError):
        memory_run.no_such_attribute  # noqa: B018


def test_saved_run_is_read_by_the_commands_and_load_run(memory_run, tmp_path, capsys):
    folder = memory_run.save(tmp_path / "run")
    loaded = mimics.load_run(folder)
    assert loaded.summary["run_uuid"] == memory_run.summary["run_uuid"]
    pd.testing.assert_frame_equal(loaded.trajectory, memory_run.trajectory)
    assert loaded.log_path(0).is_file()  # "auto" logs: 4 robots
    assert main(["report", str(folder)]) == 0
    assert "circle_swap / wall_aware / seed 2" in capsys.readouterr().out
    assert main(["replay", str(folder), "--gif", str(tmp_path / "r.gif"), "--speed", "3"]) == 0
    # saving again into the same folder replaces the run; a foreign folder is refused
    assert memory_run.save(folder) == folder
    (tmp_path / "mine").mkdir()
    (tmp_path / "mine" / "summary.txt").write_text("my notes")
    with pytest.raises(MimicsError, match="not a run folder"):
        memory_run.save(tmp_path / "mine")


def test_plot_is_the_figure_of_mimics_plot(memory_run, tmp_path):
    figure = memory_run.plot()
    assert isinstance(figure, Figure)
    folder = memory_run.save(tmp_path / "run")
    assert main(["plot", str(folder), "--out", str(tmp_path / "cli.png")]) == 0
    from_cli = imageio.imread(tmp_path / "cli.png")
    from_view = imageio.imread(io.BytesIO(png_bytes(figure)))
    assert from_view.shape == from_cli.shape == (800, 1000, 4)
    assert np.array_equal(from_view, from_cli)


def frames_expected(duration: float, fps: float, speed: float) -> int:
    """Frames every speed/fps simulated seconds from 0, plus the end when it falls between."""
    step = speed / fps
    whole = math.floor(duration / step + 1e-9)
    return whole + 1 + (duration - whole * step > 1e-9)


def test_animate_is_an_inline_video_of_the_replay_frames(memory_run):
    animation = memory_run.animate(fps=10, speed=2)
    expected = frames_expected(3.0, 10, 2)  # 0, 0.2, ... 3.0: 16 frames
    assert expected == 16 and animation.frames == expected
    html = animation._repr_html_()
    assert f'data-frames="{expected}"' in html
    data = base64.b64decode(re.search(r'base64,([^"]+)"', html).group(1))
    assert data == animation.video
    decoded = imageio.imread(data, index=None, extension=".mp4")
    assert decoded.shape[0] == expected
    assert decoded.shape[1:] == (animation.height, animation.width, 3)
    assert not np.array_equal(decoded[0], decoded[-1])  # the robots moved


def test_animate_thins_a_long_run_to_its_frame_budget():
    run = mimics.simulate("line", "go_to_goal", robots=2, time=12.0, seed=1)
    duration = run.summary["sim_time"]
    animation = run.animate(fps=10, max_frames=40)
    # 1x gives 121 frames, 2x 61, 4x 31: the first round speed within 40 frames
    assert animation.speed == 4.0
    assert animation.frames == frames_expected(duration, 10, 4.0)
    with pytest.raises(MimicsError, match="max_frames"):
        run.animate(max_frames=1)


def test_repr_html_shows_the_summary_table_and_the_figure(memory_run):
    html = memory_run._repr_html_()
    assert html.count("<tr>") >= 10 and "<th style=\"text-align:left\">robots</th>" in html
    assert html.count("data:image/png;base64,") == 1


def test_out_writes_the_folder_and_returns_the_same_object(tmp_path):
    run = mimics.simulate("line", "go_to_goal", robots=2, time=1.0, seed=1, out=tmp_path)
    assert run.path == tmp_path and (tmp_path / "summary.json").is_file()
    assert type(run) is type(mimics.load_run(tmp_path)) is mimics.RunView
    assert run.summary()["robots"] == 2 and len(run.trajectory) == 2 * 11


def test_a_run_too_big_to_keep_in_memory_is_refused_before_it_runs(monkeypatch, tmp_path):
    from mimics.catalog import load_scenario
    from mimics.records import resources

    # 1,000 robots x 1,200 steps: 1.2 million rows; a folder's recorder holds 1,048,576
    # of them at most, memory holds them all. Between the two figures: refused in memory.
    scenario = load_scenario("line", robots=1000)
    on_disk = resources.run_memory(scenario, time=120.0).total
    in_memory = resources.run_memory(scenario, time=120.0, flush_rows=2**62).total
    assert in_memory - on_disk == resources.ROW_BYTES * (1000 * 1202 - 1_048_576)
    monkeypatch.setattr(resources, "available_memory", lambda: (on_disk + in_memory) // 2)
    with pytest.raises(MimicsError, match=r"in memory needs about .* give out=FOLDER"):
        mimics.simulate("line", "go_to_goal", robots=1000, time=120.0)
