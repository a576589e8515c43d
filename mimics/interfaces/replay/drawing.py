"""Drawing a replay at any simulated time into a renderer (``interfaces.render``)."""

from __future__ import annotations

from typing import Any

from mimics.interfaces.render import WorldRenderer
from mimics.interfaces.replay.beams import BeamCaster
from mimics.interfaces.replay.frames import ReplayData
from mimics.world.errors import MimicsError


class Replayer:
    """Draws a :class:`ReplayData` at any simulated time into a renderer.

    Args:
        data: the run's dense arrays.
        renderer: where to draw (see :meth:`create`).
        trail: seconds of trail behind each robot.
        robot_beams: robot whose laser beams are recomputed and drawn, or None.
    """

    def __init__(self, data: ReplayData, renderer: WorldRenderer, *, trail: float = 5.0,
                 robot_beams: int | None = None) -> None:
        if robot_beams is not None and not 0 <= robot_beams < data.n:
            raise MimicsError(f"replay: robot {robot_beams} for beams is not in 0..{data.n - 1}")
        self.data = data
        self.renderer = renderer
        self.trail = trail
        self.trail_points = 16 if data.n <= 300 else 6
        self.robot_beams = robot_beams
        assert data.walls is not None
        self.caster = (None if robot_beams is None
                       else BeamCaster.available(data.scenario, data.walls.sets))

    @classmethod
    def create(cls, data: ReplayData, *, width_px: int = 800, extra_bottom_px: int = 0,
               figure: Any = None, **options: Any) -> Replayer:
        """A replayer drawing into a new renderer (off-screen unless ``figure`` is given)."""
        hl, hw = data.half_sizes
        m = data.scenario.map
        renderer = WorldRenderer.create(data.walls_at(0), m.bounds, hl, hw, data.scenario.goals,
                                        width_px=width_px, extra_bottom_px=extra_bottom_px,
                                        figure=figure, title=data.title)
        return cls(data, renderer, **options)

    def show_at(self, t: float) -> int:
        """Set the renderer to the state at simulated time ``t``; returns the step index."""
        data = self.data
        k = data.index_at(t)
        beams = None
        if self.caster is not None and self.robot_beams is not None:
            beams = self.caster.beams(self.robot_beams, data.pose[k], data.status[k],
                                      int(data.wall_set[k]))
        self.renderer.set_walls(data.walls_at(k))  # an edited run's walls and goals then
        self.renderer.set_goals(data.goals_at(k))
        self.renderer.update(data.pose[k], data.status[k], max(float(t), 0.0) if
                             t <= data.duration else data.duration,
                             livelock=data.livelock[k],
                             trails=data.trails(k, self.trail, self.trail_points), beams=beams)
        return k
