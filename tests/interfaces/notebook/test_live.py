"""mimics.show's widget in this process (no page): its frames, controls and run.

The page side is driven in a real JupyterLab by test_live_jupyterlab.py; here
the kernel side: the frames are PNGs of the renderer's picture, Step adds one,
and the run it records is the run mimics.simulate makes with the same seed.
"""

from __future__ import annotations

import io
import math

import imageio.v3 as imageio
import pandas as pd
import pytest

import mimics
from mimics.interfaces.notebook.animation import Animation
from mimics.interfaces.notebook.live import show
from mimics.interfaces.notebook.widget import LiveWidget
from mimics.records.runner import prepare
from mimics.world.errors import MimicsError


def test_widget_frames_steps_and_records_the_same_run_as_simulate():
    sim = prepare("circle_swap", "wall_aware", robots=4, time=2.0, seed=5)
    view = LiveWidget(sim, speed=math.inf, autoplay=False, width_px=320)
    view.step()
    view.step()
    view.stepper.wait_paused()
    assert view.frames == 3 and view.state == "paused"  # time 0, then two steps
    assert view.time == pytest.approx(0.2)
    picture = imageio.imread(io.BytesIO(view.frame))
    width, height = view.drawer.renderer.figure.canvas.get_width_height()
    assert picture.shape[:2] == (height, width)  # the renderer's canvas, as PNG
    with pytest.raises(MimicsError, match="not ended"):
        _ = view.run
    run = view.wait(timeout=120)
    assert view.state == "ended" and view.status == "time_limit"
    straight = mimics.simulate("circle_swap", "wall_aware", robots=4, time=2.0, seed=5)
    columns = ["time", "step", "robot", "x", "y", "theta", "status"]
    pd.testing.assert_frame_equal(run.trajectory[columns], straight.trajectory[columns])
    view.close()


def test_page_commands_reach_the_stepper():
    sim = prepare("line", "go_to_goal", robots=2, time=600.0, seed=1)
    view = LiveWidget(sim, speed=math.inf, autoplay=False)
    for count in (1, 2, 3):
        view._on_message(view, {"command": "step"}, [])
        view.stepper.wait_paused()
        assert sim.state.step == count
    assert sim.state.time == 0.1 + 0.1 + 0.1 != 0.3  # the engine's sum of steps...
    assert view.time == 0.3  # ...shown rounded
    view._on_message(view, {"command": "stop"}, [])
    view.stepper.wait_ended(timeout=60)
    # Stop ends the run where it is: no step more
    assert view.state == "ended" and view.status == "stopped" and sim.state.step == 3
    view._on_message(view, {"command": "rm -rf"}, [])  # anything else is ignored
    view.close()


def test_without_widgets_show_returns_the_replay():
    # not in a Jupyter kernel here: the run goes to its end and comes back as its replay
    shown = show("line", "go_to_goal", robots=2, time=1.0, seed=1)
    assert isinstance(shown, Animation) and shown.frames == 11
    with pytest.raises(MimicsError, match="speed"):
        show("line", "go_to_goal", speed=-1, widget=False)
