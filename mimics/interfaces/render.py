"""One renderer of a world state, shared by the live view, replays and plots.

The engine never draws (STYLE item 11): this module takes plain arrays —
poses, statuses, half sizes, goals, optional trails and beams — and draws them
with Matplotlib collections that are updated in place each frame (a
``PolyCollection`` whose vertices are reset, ``LineCollection`` objects for
trails, headings and beams), so that thousands of robots draw quickly. Off
screen, frames come from an Agg canvas by blitting: the static layer (walls,
goals, legend) is drawn once and only the moving artists are redrawn.

>>> import numpy as np
>>> r = WorldRenderer.create(np.array([[0, 0, 4, 0]]), (-1, -1, 5, 3),
...                          half_length=np.array([0.35]), half_width=np.array([0.25]))
>>> r.update(np.array([[1.0, 1.0, 0.0]]), np.array([0], dtype=np.int8), time=2.5)
>>> r.to_rgb().shape
(576, 800, 3)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.colors import to_rgba_array
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from mimics.engine.state import Status
from mimics.world.maps import Bounds

#: Colour of each robot state; ``livelock`` marks active robots in a livelock.
STATUS_COLORS: dict[str, str] = {
    "active": "#1f77b4",
    "reached_goal": "#2ca02c",
    "collided": "#d62728",
    "escaped": "#8c8c8c",
    "deadlock": "#ff7f0e",
    "livelock": "#9467bd",
    "error": "#e377c2",
    "removed": "#d9d9d9",
}
BACKGROUND = "#ffffff"
WALL_COLOR = "#222222"
GOAL_COLOR = "#7a7a7a"
BEAM_COLOR = "#d62728"
HEADING_COLOR = "#ffffff"
STATE_NAMES = (*(s.label for s in Status), "livelock")  # rows of the colour table
_LIVELOCK = len(Status)  # row of the colour table used for active robots in livelock
_STRIP_PX = 48  # height of the strip under the map with the time and the legend


def status_color_table(colors: dict[str, str] | None = None) -> np.ndarray:
    """RGBA rows indexed by ``Status`` value, plus one last row for livelock."""
    colors = {**STATUS_COLORS, **(colors or {})}
    return to_rgba_array([colors[name] for name in STATE_NAMES])


def rectangle_vertices(pose: np.ndarray, half_length: np.ndarray,
                       half_width: np.ndarray) -> np.ndarray:
    """Corners ``(n, 4, 2)`` of oriented rectangles, counter-clockwise from front-left.

    Args:
        pose: ``(n, 3)`` centre x, y and heading theta.
        half_length: ``(n,)`` half sizes along the heading.
        half_width: ``(n,)`` half sizes across it.
    """
    x, y, theta = pose[:, 0:1], pose[:, 1:2], pose[:, 2:3]
    c, s = np.cos(theta), np.sin(theta)
    lx = half_length[:, None] * np.array([1.0, -1.0, -1.0, 1.0])
    ly = half_width[:, None] * np.array([1.0, 1.0, -1.0, -1.0])
    return np.stack([x + c * lx - s * ly, y + s * lx + c * ly], axis=-1)


def beam_segments(origin: Sequence[float], heading: float, offsets: np.ndarray,
                  ranges: np.ndarray) -> np.ndarray:
    """Laser beams as segments ``(k, 2, 2)`` from the robot to each range's end.

    Beams whose offset or range is NaN (types with fewer beams) are left out.
    """
    keep = np.isfinite(offsets) & np.isfinite(ranges)
    angles = heading + offsets[keep]
    dist = ranges[keep]
    ox, oy = float(origin[0]), float(origin[1])
    segs = np.empty((angles.size, 2, 2))
    segs[:, 0, 0], segs[:, 0, 1] = ox, oy
    segs[:, 1, 0] = ox + dist * np.cos(angles)
    segs[:, 1, 1] = oy + dist * np.sin(angles)
    return segs


def figure_size(bounds: Bounds, width_px: int = 800, extra_px: int = _STRIP_PX,
                pad: float = 0.02) -> tuple[int, int, tuple[float, float, float, float]]:
    """Pixel size of a figure showing ``bounds`` undistorted, and the padded limits.

    The longer side of the map gets ``width_px`` pixels; both figure sides are
    multiples of 16 so that video encoders need not resize frames.
    """
    xmin, ymin, xmax, ymax = bounds
    dx, dy = (xmax - xmin) * pad, (ymax - ymin) * pad
    limits = (xmin - dx, ymin - dy, xmax + dx, ymax + dy)
    aspect = (limits[3] - limits[1]) / (limits[2] - limits[0])
    if aspect <= 1.0:
        w_ax, h_ax = width_px, width_px * aspect
    else:
        w_ax, h_ax = width_px / aspect, width_px
    w_ax = max(w_ax, 480.0)  # room for the legend under very tall maps
    width = int(16 * round(w_ax / 16))
    height = int(16 * round((h_ax + extra_px) / 16))
    height = max(height, extra_px + 64)
    return width, height, limits


class WorldRenderer:
    """Draws one world state into a Matplotlib axes; call :meth:`update` per frame.

    Args:
        ax: the axes to draw into (its figure holds the time text and legend).
        segments: ``(m, 4)`` wall segments.
        bounds: ``(xmin, ymin, xmax, ymax)`` of the map (drawn as a thin frame).
        half_length: ``(n,)`` half size of each robot along its heading.
        half_width: ``(n,)`` half size across it.
        goals: ``(n, 2)`` goals, NaN rows for robots without one.
        limits: axes limits; default the bounds.
        colors: overrides of :data:`STATUS_COLORS`.
        legend: draw a legend of the robot states under the map.
        title: text above the time, e.g. the scenario and algorithm.
        strip_bottom_px: height of the figure's strip for the time and legend above
            its bottom edge (room for widgets under it).
    """

    def __init__(self, ax: Axes, segments: np.ndarray, bounds: Bounds,
                 half_length: np.ndarray, half_width: np.ndarray,
                 goals: np.ndarray | None = None, *,
                 limits: tuple[float, float, float, float] | None = None,
                 colors: dict[str, str] | None = None, legend: bool = True,
                 title: str = "", strip_bottom_px: float = 0.0) -> None:
        self.ax = ax
        self.figure: Figure = ax.figure  # type: ignore[assignment]
        self.half_length = np.asarray(half_length, dtype=np.float64)
        self.half_width = np.asarray(half_width, dtype=np.float64)
        self.n = self.half_length.size
        self.title = title
        self._table = status_color_table(colors)
        self._trail_alpha = 0.35
        self._background: Any = None
        self._bg_size: tuple[int, int] = (0, 0)
        xmin, ymin, xmax, ymax = limits or bounds
        ax.set_xlim(xmin, xmax)
        ax.set_ylim(ymin, ymax)
        ax.set_aspect("equal", adjustable="box")
        ax.set_facecolor(BACKGROUND)
        ax.set_xticks([])
        ax.set_yticks([])
        for spine in ax.spines.values():
            spine.set_color("#bbbbbb")
        bx0, by0, bx1, by1 = bounds
        frame = np.array([[bx0, by0], [bx1, by0], [bx1, by1], [bx0, by1], [bx0, by0]])
        ax.plot(frame[:, 0], frame[:, 1], color="#cccccc", lw=0.8, ls="--", zorder=1)
        self._wall_source = segments
        self._walls = LineCollection(np.asarray(segments, dtype=np.float64).reshape(-1, 2, 2),
                                     colors=WALL_COLOR, linewidths=1.5, zorder=2)
        ax.add_collection(self._walls)
        self._goals = Line2D([], [], ls="none", marker="x", markersize=4, color=GOAL_COLOR,
                             markeredgewidth=1.0, zorder=3)
        ax.add_line(self._goals)
        self._goals_shown: np.ndarray | None = None
        self.set_goals(goals)
        empty = np.zeros((0, 2, 2))
        self._trails = LineCollection(empty, linewidths=1.0, zorder=4)
        self._beams = LineCollection(empty, colors=BEAM_COLOR, linewidths=0.6, alpha=0.55,
                                     zorder=5)
        start = rectangle_vertices(np.zeros((self.n, 3)), self.half_length, self.half_width)
        self._bodies = PolyCollection(start, closed=True, linewidths=0.6, zorder=6)
        self._headings = LineCollection(np.zeros((self.n, 2, 2)), colors=HEADING_COLOR,
                                        linewidths=0.8, zorder=7)
        for artist in (self._trails, self._beams, self._bodies, self._headings):
            ax.add_collection(artist, autolim=False)
        height = self.figure.bbox.height
        self._text = self.figure.text(0.01, (strip_bottom_px + 6) / height, "t = 0.00 s",
                                      fontsize=9, va="bottom", ha="left")
        self.figure.text(0.01, (strip_bottom_px + 22) / height, title, fontsize=9,
                         va="bottom", ha="left")
        self._counts: tuple[int, ...] = ()
        self._legend = None
        if legend:
            handles = [Patch(facecolor=c, edgecolor=c, label=name.replace("_", " "))
                       for name, c in zip(STATE_NAMES, self._table, strict=True)]
            self._legend = self.figure.legend(
                handles=handles, loc="lower right", ncol=4, fontsize=7, frameon=False,
                handlelength=1.0, columnspacing=0.8,
                bbox_to_anchor=(1.0, strip_bottom_px / height))
        # Redrawn every frame; the rest (walls, goals, title, legend) is the cached static
        # layer, redrawn only when the goals or the counts in the legend change.
        self.dynamic: list[Artist] = [self._trails, self._beams, self._bodies, self._headings,
                                      self._text]

    @classmethod
    def create(cls, segments: np.ndarray, bounds: Bounds, half_length: np.ndarray,
               half_width: np.ndarray, goals: np.ndarray | None = None, *,
               width_px: int = 800, extra_bottom_px: int = 0, figure: Figure | None = None,
               **options: Any) -> WorldRenderer:
        """A renderer in a new figure sized to the map (an off-screen Agg one by default).

        Args:
            segments: ``(m, 4)`` wall segments.
            bounds: map bounds.
            half_length: ``(n,)`` half lengths.
            half_width: ``(n,)`` half widths.
            goals: ``(n, 2)`` goals or None.
            width_px: pixels of the longer side of the map.
            extra_bottom_px: more room under the map (for widgets).
            figure: an empty figure to use (e.g. from pyplot for a window); it is resized.
            **options: passed to the constructor (colors, legend, title).
        """
        width, height, limits = figure_size(bounds, width_px, _STRIP_PX + extra_bottom_px)
        dpi = 100.0
        if figure is None:
            figure = Figure(figsize=(width / dpi, height / dpi), dpi=dpi, facecolor=BACKGROUND)
            FigureCanvasAgg(figure)
        else:
            figure.set_dpi(dpi)
            figure.set_size_inches(width / dpi, height / dpi)
            figure.set_facecolor(BACKGROUND)
        bottom = (_STRIP_PX + extra_bottom_px) / height
        ax = figure.add_axes((0.0, bottom, 1.0, 1.0 - bottom))
        return cls(ax, segments, bounds, half_length, half_width, goals, limits=limits,
                   strip_bottom_px=extra_bottom_px, **options)

    def set_goals(self, goals: np.ndarray | None) -> None:
        """Show these goals (``(n, 2)``, NaN rows hidden); they belong to the static layer
        (the goals shown again change nothing)."""
        shown = self._goals_shown
        if goals is not None and shown is not None and np.array_equal(
                shown, np.asarray(goals, dtype=np.float64), equal_nan=True):
            return
        self._goals_shown = None if goals is None else np.array(goals, dtype=np.float64)
        if goals is None or len(goals) == 0:
            self._goals.set_data([], [])
        else:
            g = np.asarray(goals, dtype=np.float64)
            self._goals.set_data(g[:, 0], g[:, 1])
        self._background = None

    def set_walls(self, segments: np.ndarray) -> None:
        """Show these walls ``(m, 4)`` (a run edited as it runs); the same array again
        changes nothing. They belong to the static layer."""
        if segments is self._wall_source:
            return
        self._wall_source = segments
        self._walls.set_segments(np.asarray(segments, dtype=np.float64).reshape(-1, 2, 2))
        self._background = None

    def update(self, pose: np.ndarray, status: np.ndarray, time: float, *,
               livelock: np.ndarray | None = None, trails: np.ndarray | None = None,
               beams: np.ndarray | None = None) -> None:
        """Set the moving artists to a new world state (nothing is drawn yet).

        Args:
            pose: ``(n, 3)`` true x, y, theta.
            status: ``(n,)`` ``Status`` codes.
            time: simulated time (s).
            livelock: ``(n,)`` bool, active robots currently in a livelock.
            trails: ``(n, k, 2)`` recent positions per robot, oldest first (NaN gaps ok).
            beams: ``(b, 2, 2)`` laser beam segments (see :func:`beam_segments`).
        """
        pose = np.asarray(pose, dtype=np.float64)
        status = np.asarray(status)
        colour_index = status.astype(np.intp)
        if livelock is not None:
            colour_index = np.where(livelock & (status == Status.ACTIVE), _LIVELOCK,
                                    colour_index)
        colours = self._table[colour_index]
        verts = rectangle_vertices(pose, self.half_length, self.half_width)
        self._bodies.set_verts(verts)
        self._bodies.set_facecolor(colours)
        self._bodies.set_edgecolor(colours)
        c, s = np.cos(pose[:, 2]), np.sin(pose[:, 2])
        heading = np.empty((self.n, 2, 2))
        for end, frac in ((0, 0.5), (1, 1.0)):
            heading[:, end, 0] = pose[:, 0] + frac * self.half_length * c
            heading[:, end, 1] = pose[:, 1] + frac * self.half_length * s
        self._headings.set_segments(heading)
        self._headings.set_visible(self._pixels_per_metre() * self.half_length.min(initial=1.0)
                                   >= 3.0)
        if trails is not None and trails.shape[1] > 1:
            self._trails.set_segments(trails)
            trail_colours = colours.copy()
            trail_colours[:, 3] = self._trail_alpha
            self._trails.set_color(trail_colours)
        else:
            self._trails.set_segments(np.zeros((0, 2, 2)))
        self._beams.set_segments(np.zeros((0, 2, 2)) if beams is None else beams)
        self._text.set_text(f"t = {time:.2f} s")
        if self._legend is not None:
            counts = tuple(np.bincount(colour_index, minlength=len(self._table)).tolist())
            if counts != self._counts:
                self._counts = counts
                for text, name, count in zip(self._legend.get_texts(), STATE_NAMES, counts,
                                             strict=True):
                    text.set_text(f"{name.replace('_', ' ')} {count}")
                self._background = None

    def _pixels_per_metre(self) -> float:
        x0, x1 = self.ax.get_xlim()
        return float(self.ax.bbox.width / max(x1 - x0, 1e-12))

    def to_rgb(self) -> np.ndarray:
        """The current frame as an ``(height, width, 3)`` uint8 array (Agg canvases).

        The static layer is drawn once and cached (again when the goals or the
        counts of robots per state change); other frames only restore it and
        draw the moving artists over it.
        """
        canvas = self.figure.canvas
        size = canvas.get_width_height()
        if self._background is None or size != self._bg_size:
            visible = [artist.get_visible() for artist in self.dynamic]
            for artist in self.dynamic:
                artist.set_visible(False)
            canvas.draw()
            self._background = canvas.copy_from_bbox(self.figure.bbox)  # type: ignore[attr-defined]
            self._bg_size = size
            for artist, shown in zip(self.dynamic, visible, strict=True):
                artist.set_visible(shown)
        canvas.restore_region(self._background)  # type: ignore[attr-defined]
        for artist in self.dynamic:
            self.figure.draw_artist(artist)
        return np.asarray(canvas.buffer_rgba())[..., :3]  # type: ignore[attr-defined]

    def refresh(self) -> None:
        """Redraw an on-screen figure and let its window process events."""
        self._background = None
        self.figure.canvas.draw_idle()
        self.figure.canvas.flush_events()

    def world_to_pixel(self, xy: np.ndarray) -> np.ndarray:
        """Image ``(column, row)`` of world points ``(k, 2)``, row 0 at the top."""
        display = self.ax.transData.transform(np.asarray(xy, dtype=np.float64).reshape(-1, 2))
        height = self.figure.canvas.get_width_height()[1]
        return np.column_stack([display[:, 0], height - display[:, 1]])

    def color_of(self, name: str) -> tuple[int, int, int]:
        """The 8-bit RGB colour this renderer gives a state (a name of :data:`STATE_NAMES`)."""
        rgba = self._table[STATE_NAMES.index(name)]
        return tuple(int(255 * float(v) + 0.5) for v in rgba[:3])  # type: ignore[return-value]
