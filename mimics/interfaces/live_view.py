"""Live view of a running simulation at the paper's three representation times.

``LiveView`` is an observer of :class:`mimics.engine.simulation.Simulation`: it
draws the world with :class:`mimics.interfaces.render.WorldRenderer` at time 0,
then every step (``"step"``), every simulated second (``"1s"``) or every 10
simulated seconds (``"10s"``), and once more at the end if the final state
fell between two representation times. ``"off"`` draws nothing, and
:func:`make_live_view` returns no observer at all for it, so that batteries pay
nothing. Where no display exists the view says so in one line and does nothing
(record a video of the run instead); ``offscreen=True`` renders into an Agg
canvas, for tests, benchmarks or a caller that wants the frames.

>>> view = LiveView("1s", offscreen=True)
>>> view.period
1.0
>>> make_live_view("off") is None
True
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.state import Status
from mimics.world.errors import MimicsError

if TYPE_CHECKING:  # matplotlib costs ~0.5 s to import: only a shown view needs it
    from mimics.interfaces.render import WorldRenderer

#: Representation times accepted by ``mimics run --view``: seconds between frames.
MODES: dict[str, float] = {"step": 0.0, "1s": 1.0, "10s": 10.0}
VIEW_CHOICES = (*MODES, "off")
_EPS = 1e-9


def has_display() -> bool:
    """True when Matplotlib can open a window here (a display and a GUI backend)."""
    if (sys.platform.startswith(("linux", "freebsd", "openbsd"))
            and not (os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"))):
        return False
    import matplotlib
    from matplotlib.backends import BackendFilter, backend_registry

    backend = matplotlib.get_backend().lower()
    headless = {b.lower() for b in backend_registry.list_builtin(BackendFilter.NON_INTERACTIVE)}
    return backend not in headless


def no_display_notice(mode: str) -> str:
    """The one line printed when a live view is asked for without a display."""
    return (f"mimics: no display for the live view (--view {mode}); running without it "
            "(record the run with --video run.mp4 instead)")


class TrailBuffer:
    """The last few positions of every robot, sampled every ``every`` steps (a ring).

    Args:
        n: number of robots.
        points: positions kept per robot.
        every: keep one position out of ``every`` pushes.
    """

    def __init__(self, n: int, points: int, every: int) -> None:
        self.points = max(1, int(points))
        self.every = max(1, int(every))
        self._ring = np.full((self.points, n, 2), np.nan)
        self._head = 0
        self._pushes = 0

    def push(self, xy: np.ndarray) -> None:
        """Offer the positions ``(n, 2)`` of one step; one in ``every`` is kept."""
        if self._pushes % self.every == 0:
            self._ring[self._head] = xy
            self._head = (self._head + 1) % self.points
        self._pushes += 1

    def forget(self, robot: int) -> None:
        """Drop ``robot``'s kept positions (an edit moved it: no line across the jump)."""
        self._ring[:, robot] = np.nan

    def segments(self, current: np.ndarray) -> np.ndarray:
        """Polylines ``(n, points + 1, 2)``, oldest first, ending at ``current``."""
        ordered = np.roll(self._ring, -self._head, axis=0)
        return np.concatenate([ordered, current[None]], axis=0).transpose(1, 0, 2)


def trail_shape(n: int, seconds: float, dt: float) -> tuple[int, int]:
    """Points per trail and steps between them for ``n`` robots and a trail of ``seconds``.

    Long trails of thousands of robots cost the most to draw, so large teams get
    fewer points.
    """
    points = 16 if n <= 300 else 6
    steps = max(1, round(seconds / dt))
    every = max(1, math.ceil(steps / points))
    return min(points, steps), every


class LiveView:
    """An observer that draws the world while a simulation runs.

    Args:
        mode: ``"step"``, ``"1s"``, ``"10s"`` or ``"off"`` (draws nothing).
        offscreen: render into an Agg canvas instead of a window.
        trail: seconds of trail behind each robot (0 for none).
        beams_of: index of a robot whose laser beams are drawn, or None.
        width_px: pixels of the longer side of the map.
        hold: in a window, keep it open at the end until the user closes it.
        on_frame: called with ``(time, rgb)`` after each off-screen frame; ``rgb``
            is the canvas buffer, valid until the next frame (copy it to keep it).

    Attributes:
        drawn_times: simulated times of the frames drawn so far.
        renderer: the renderer, once the run has started (None when inactive).
    """

    def __init__(self, mode: str = "1s", *, offscreen: bool = False, trail: float = 5.0,
                 beams_of: int | None = None, width_px: int = 800, hold: bool = True,
                 on_frame: Callable[[float, np.ndarray], Any] | None = None) -> None:
        if mode not in VIEW_CHOICES:
            raise MimicsError(f"view: expected one of {', '.join(VIEW_CHOICES)}, got {mode!r}")
        if trail < 0:
            raise MimicsError(f"view: trail must be >= 0 seconds, got {trail}")
        self.mode = mode
        self.period = MODES.get(mode, math.inf)
        self.offscreen = offscreen
        self.trail = trail
        self.beams_of = beams_of
        self.width_px = width_px
        self.hold = hold
        self.on_frame = on_frame
        self.enabled = mode != "off"
        self.drawn_times: list[float] = []
        self.renderer: WorldRenderer | None = None
        self._trails: TrailBuffer | None = None
        self._last_index = -1
        self._window: Any = None

    # -- observer hooks ----------------------------------------------------

    def on_start(self, sim: Any) -> None:
        """Build the figure and draw the state at time 0."""
        if not self.enabled:
            return
        if not self.offscreen and not has_display():
            print(no_display_notice(self.mode), file=sys.stderr)
            self.enabled = False
            return
        state, types, scenario = sim.state, sim.types, sim.scenario
        if self.beams_of is not None and not 0 <= self.beams_of < state.n:
            raise MimicsError(f"view: robot {self.beams_of} for beams is not in 0..{state.n - 1}")
        title = f"{scenario.name} / {sim.controller.name} / seed {sim.seed}"
        figure = None
        if not self.offscreen:
            import matplotlib.pyplot as plt

            figure = plt.figure(num=f"mimics: {title}")
            self._window = plt
        from mimics.interfaces.render import WorldRenderer

        self.renderer = WorldRenderer.create(
            scenario.map.segments, scenario.map.bounds, types.half_length, types.half_width,
            state.goal, width_px=self.width_px, figure=figure, title=title)
        if self.trail > 0:
            points, every = trail_shape(state.n, self.trail, scenario.settings.dt)
            self._trails = TrailBuffer(state.n, points, every)
            self._trails.push(state.pose[:, :2])
        if self._window is not None:
            self._window.show(block=False)
        self._draw(sim)
        self._last_index = 0

    def on_step(self, sim: Any) -> None:
        """Record the trail; draw if this step reaches the next representation time."""
        if not self.enabled:
            return
        if self._trails is not None:
            self._trails.push(sim.state.pose[:, :2])
        if self.period == 0.0:
            self._draw(sim)
            return
        index = math.floor(sim.state.time / self.period + _EPS)
        if index > self._last_index:
            self._last_index = index
            self._draw(sim)

    def on_edit(self, sim: Any, applied: Any) -> None:
        """An edit moved a robot: its trail starts again at its new place (the walls and
        goals an edit changes are drawn with the next frame, see :func:`draw_world`)."""
        if self.enabled:
            forget_moved(self._trails, applied)

    def on_end(self, sim: Any, result: Any) -> None:
        """Draw the final state if it was not drawn yet; in a window, optionally wait."""
        if not self.enabled:
            return
        if not self.drawn_times or sim.state.time > self.drawn_times[-1] + _EPS:
            self._draw(sim)
        if self._window is not None and self.hold and self._window_open():
            self._window.show(block=True)

    # -- drawing -----------------------------------------------------------

    def _window_open(self) -> bool:
        assert self.renderer is not None
        return bool(self._window.fignum_exists(self.renderer.figure.number))

    def _draw(self, sim: Any) -> None:
        renderer = self.renderer
        if renderer is None:
            return
        if self._window is not None and not self._window_open():
            self.enabled = False  # the user closed the window: the run goes on without it
            return
        draw_world(renderer, sim, self.beams_of, self._trails)
        state = sim.state
        self.drawn_times.append(float(state.time))
        if self.offscreen:
            rgb = renderer.to_rgb()
            if self.on_frame is not None:
                self.on_frame(float(state.time), rgb)
        else:
            renderer.refresh()

    def frame(self) -> np.ndarray:
        """A copy of the last off-screen frame, ``(height, width, 3)`` uint8."""
        if self.renderer is None:
            raise MimicsError("view: nothing has been drawn yet")
        canvas = self.renderer.figure.canvas
        return np.asarray(canvas.buffer_rgba())[..., :3].copy()  # type: ignore[attr-defined]


def make_live_view(mode: str, *, offscreen: bool = False, **options: Any) -> LiveView | None:
    """The observer for ``mimics run --view MODE``, or None when it would draw nothing.

    ``"off"`` gives None (no observer, no cost). Without a display (and not
    ``offscreen``) it prints one line suggesting ``--video`` and gives None.

    Args:
        mode: ``"step"``, ``"1s"``, ``"10s"`` or ``"off"``.
        offscreen: render into an Agg canvas instead of a window.
        **options: passed to :class:`LiveView` (trail, beams_of, width_px, hold, on_frame).

    Raises:
        MimicsError: for an unknown mode.
    """
    if mode not in VIEW_CHOICES:
        raise MimicsError(f"--view: expected one of {', '.join(VIEW_CHOICES)}, got {mode!r}")
    if mode == "off":
        return None
    if not offscreen and not has_display():
        print(no_display_notice(mode), file=sys.stderr)
        return None
    return LiveView(mode, offscreen=offscreen, **options)


def forget_moved(trails: TrailBuffer | None, applied: Any) -> None:
    """Drop the trail of a robot an applied edit (``on_edit``'s) moved."""
    edit = getattr(applied, "edit", applied)
    if trails is not None and edit.kind == "move_robot" and edit.robot is not None:
        trails.forget(int(edit.robot))


def draw_world(renderer: Any, sim: Any, beams_of: int | None,
               trails: TrailBuffer | None) -> None:
    """Bring ``renderer`` up to the simulation's state: the walls and goals as edited so
    far (``sim.world_map``; redrawn only when an edit changed them), the robots, their
    trails, and the beams of robot ``beams_of`` (None: no beams; nor for a stopped or blind
    robot)."""
    state = sim.state
    world = getattr(sim, "world_map", None)
    renderer.set_walls((sim.scenario.map if world is None else world).segments)
    renderer.set_goals(state.goal)  # a set_goal edit may have moved one
    beams = None
    i = beams_of
    if i is not None and state.status[i] == Status.ACTIVE and sim.types.beam_count[i] > 0:
        from mimics.interfaces.render import beam_segments

        beams = beam_segments(state.pose[i, :2], state.pose[i, 2], sim.types.beam_offsets[i],
                              state.scan[i])
    segments = None if trails is None else trails.segments(state.pose[:, :2])
    renderer.update(state.pose, state.status, state.time, livelock=state.in_livelock,
                    trails=segments, beams=beams)
