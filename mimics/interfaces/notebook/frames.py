"""The live view's frames: an observer that keeps the robots' trails and draws a frame,
as PNG bytes, on request (for the notebook widget; the replay's renderer draws them)."""

from __future__ import annotations

import io
from typing import Any

import numpy as np

from mimics.interfaces.live_view import TrailBuffer, draw_world, forget_moved, trail_shape
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

    def on_edit(self, sim: Any, applied: Any) -> None:
        """An edit moved a robot: its trail starts again at its new place (the edited walls
        and goals are drawn with the next frame)."""
        forget_moved(self._trails, applied)

    def png(self, sim: Any) -> bytes:
        """The world now, as PNG bytes."""
        from PIL import Image

        draw_world(self.renderer, sim, self.beams_of, self._trails)
        buffer = io.BytesIO()
        Image.fromarray(np.ascontiguousarray(self.renderer.to_rgb())).save(
            buffer, format="PNG", compress_level=1)
        return buffer.getvalue()
