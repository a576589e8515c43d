"""``mimics.show``: a simulation drawn in a notebook cell while it runs.

The cell shows an `anywidget <https://anywidget.dev>`_ widget (JupyterLab,
Notebook 7, VS Code, Colab): Play, Pause, Step, Stop and a speed choice. The
simulation steps in a background thread (:class:`~mimics.interfaces.stepper.SimulationStepper`),
so the kernel stays free: the buttons' messages are handled between cells,
and other cells can run meanwhile. Frames are drawn by the replay's and the
live view's renderer (:class:`~mimics.interfaces.render.WorldRenderer`: the
same walls, robot bodies, state colours, trails and legend) and sent to the
page as PNG bytes, at most ``fps`` a second. The run is recorded in memory, as
by ``mimics.simulate``: once it has ended, ``view.run`` is its
:class:`~mimics.interfaces.notebook.run.RunView`.

Where widgets cannot be shown (no anywidget installed, or not in a Jupyter
kernel) ``show`` runs the simulation to its end and returns its
``.animate()`` instead, saying so in one line.
"""

from __future__ import annotations

import importlib.util
import io
import math
import sys
from typing import Any

import numpy as np

from mimics.engine.state import Status
from mimics.interfaces.live_view import TrailBuffer, trail_shape
from mimics.interfaces.notebook.html import in_kernel
from mimics.world.errors import MimicsError


class FrameDrawer:
    """An observer keeping the robots' trails, drawing a frame as PNG bytes on request.

    Args:
        width_px: pixels of the longer side of the map.
        trail: seconds of trail behind each robot (0: none).
        beams_of: a robot whose laser beams are drawn, or None.
    """

    def __init__(self, width_px: int = 640, trail: float = 5.0,
                 beams_of: int | None = None) -> None:
        self.width_px = width_px
        self.trail = trail
        self.beams_of = beams_of
        self.renderer: Any = None
        self._trails: TrailBuffer | None = None

    def on_start(self, sim: Any) -> None:
        """Build the renderer for this world (the live view's, off-screen)."""
        from mimics.interfaces.render import WorldRenderer

        state, types, scenario = sim.state, sim.types, sim.scenario
        if self.beams_of is not None and not 0 <= self.beams_of < state.n:
            raise MimicsError(f"show: robot {self.beams_of} for beams is not in 0..{state.n - 1}")
        title = f"{scenario.name} / {sim.controller.name} / seed {sim.seed}"
        self.renderer = WorldRenderer.create(
            scenario.map.segments, scenario.map.bounds, types.half_length, types.half_width,
            state.goal, width_px=self.width_px, title=title)
        if self.trail > 0:
            points, every = trail_shape(state.n, self.trail, scenario.settings.dt)
            self._trails = TrailBuffer(state.n, points, every)
            self._trails.push(state.pose[:, :2])

    def on_step(self, sim: Any) -> None:
        """Keep the trails."""
        if self._trails is not None:
            self._trails.push(sim.state.pose[:, :2])

    def png(self, sim: Any) -> bytes:
        """The world now, as PNG bytes."""
        from PIL import Image

        from mimics.interfaces.render import beam_segments

        state = sim.state
        beams = None
        i = self.beams_of
        if i is not None and state.status[i] == Status.ACTIVE and sim.types.beam_count[i] > 0:
            beams = beam_segments(state.pose[i, :2], state.pose[i, 2],
                                  sim.types.beam_offsets[i], state.scan[i])
        trails = None if self._trails is None else self._trails.segments(state.pose[:, :2])
        self.renderer.update(state.pose, state.status, state.time, livelock=state.in_livelock,
                             trails=trails, beams=beams)
        buffer = io.BytesIO()
        Image.fromarray(np.ascontiguousarray(self.renderer.to_rgb())).save(
            buffer, format="PNG", compress_level=1)
        return buffer.getvalue()


def widgets_available() -> bool:
    """True where a widget can be shown: anywidget is installed and a kernel runs."""
    return importlib.util.find_spec("anywidget") is not None and in_kernel()


def show(scenario: Any, algorithm: Any, *, robots: int | None = None,
         time: float | None = None, seed: int = 0, params: dict[str, Any] | None = None,
         policy: str = "abort", speed: float = 1.0, fps: float = 10.0, width_px: int = 640,
         trail: float = 5.0, beams_of: int | None = None, autoplay: bool = True,
         widget: bool | None = None) -> Any:
    """A live view of a new simulation in the cell (a
    ``mimics.interfaces.notebook.widget.LiveWidget``).

    Args:
        scenario: a built-in name, a ``.py``/``.toml`` file or a Scenario.
        algorithm: a built-in name, a ``.py`` file, or a module/function/class.
        robots, time, seed, params, policy: as for ``mimics.simulate``.
        speed: simulated seconds per wall second (``math.inf`` or 0: as fast as possible).
        fps: frames sent to the page per second at most.
        width_px: pixels of the longer side of the map.
        trail: seconds of trail behind each robot.
        beams_of: a robot whose laser beams are drawn.
        autoplay: start playing at once (else wait for Play or Step).
        widget: None: a widget where one can be shown, else the run's ``.animate()``;
            False: always the animation.

    Raises:
        MimicsError: a bad scenario, algorithm or option (before anything runs).
    """
    from mimics.interfaces.stepper import check_speed
    from mimics.records.runner import prepare

    if speed != 0:
        check_speed(speed)
    if widget is None:
        widget = widgets_available()
    if not widget:
        from mimics.interfaces.api import simulate

        print("mimics.show: no widgets here (anywidget and a Jupyter kernel are needed): "
              "running to the end and showing the replay", file=sys.stderr)
        run = simulate(scenario, algorithm, robots=robots, time=time, seed=seed,
                       params=params, policy=policy)  # type: ignore[arg-type]
        return run.animate(fps=fps, width_px=width_px, trail=trail, robot_beams=beams_of)
    from mimics.interfaces.notebook.widget import LiveWidget

    sim = prepare(scenario, algorithm, robots=robots, time=time, seed=seed, params=params,
                  policy=policy)  # type: ignore[arg-type]
    pace = 0.0 if speed == 0 else speed
    return LiveWidget(sim, speed=pace if pace else math.inf, fps=fps, width_px=width_px,
                      trail=trail, beams_of=beams_of, autoplay=autoplay)
