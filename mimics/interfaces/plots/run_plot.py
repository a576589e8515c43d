"""One run's trajectories over the map, coloured by each robot's final state.

A run edited as it ran (``mimics.world.edits``) is drawn with its start walls
that stayed in black, the walls an edit added in :data:`ADDED_WALL_COLOR` and
those an edit removed dashed (each named in the legend), so one picture shows the
world before and after; a robot an edit moved has its line broken at the jump, and
the goals drawn are those at the end (``goal at the end`` when an edit set one).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.collections import LineCollection
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from mimics.engine.state import Status
from mimics.interfaces.plots.figures import _new_figure, _save
from mimics.interfaces.render import GOAL_COLOR, STATUS_COLORS, WALL_COLOR, status_color_table
from mimics.interfaces.replay import open_run, replay_data
from mimics.interfaces.replay.edits import break_at_moves

ADDED_WALL_COLOR = "#1f77b4"
REMOVED_WALL_COLOR = "#999999"

#: Marker and legend label of each final state in a run plot.
FINAL_MARKS: dict[int, tuple[str, str]] = {
    Status.REACHED_GOAL: ("o", "reached goal"),
    Status.COLLIDED: ("X", "collided"),
    Status.ESCAPED: ("^", "escaped"),
    Status.DEADLOCK: ("s", "deadlock"),
    Status.ERROR: ("D", "error"),
    Status.REMOVED: ("+", "removed"),
    Status.ACTIVE: (".", "active at end"),
}

def plot_run(run: str | Path | Any, out: str | Path | None, *, width_px: int = 1000,
             height_px: int = 800) -> Path | Figure:
    """Trajectories over the map with deactivation marks and a legend, as a PNG.

    Args:
        run: a run folder or a loaded run.
        out: the PNG to write (None: return the Matplotlib Figure instead).
        width_px: image width in pixels.
        height_px: image height in pixels.

    Returns:
        The path written (the Figure when ``out`` is None).

    Raises:
        MimicsError: not a run, an unreadable trajectory, or an unwritable ``out``.

    Example:
        >>> plot_run("runs/line-go_to_goal-s1", "run.png")  # doctest: +SKIP
    """
    loaded = open_run(run)
    data = replay_data(loaded)
    fig = _new_figure(width_px, height_px)
    ax = fig.add_subplot()
    scenario = data.scenario
    m = scenario.map
    handles: list[Any] = [
        Line2D([], [], ls="none", marker="o", ms=5, mfc="none", mec="#555555", label="start")]
    handles += _draw_walls(ax, data)
    xmin, ymin, xmax, ymax = m.bounds
    ax.plot([xmin, xmax, xmax, xmin, xmin], [ymin, ymin, ymax, ymax, ymin], color="#cccccc",
            lw=0.8, ls="--", zorder=1)
    table = status_color_table()
    final = data.status[-1].astype(np.intp)
    paths: Any = data.pose[:, :, :2].transpose(1, 0, 2)
    if data.moves:  # no line across a robot's jump to where an edit moved it
        paths = list(paths)
        for robot, moved_at in data.moves.items():
            paths[robot] = break_at_moves(paths[robot], data.steps, moved_at)
    ax.add_collection(LineCollection(paths, colors=table[final], linewidths=0.9, alpha=0.6,
                                     zorder=3))
    start = scenario.stages
    ax.plot(start[:, 0], start[:, 1], ls="none", marker="o", ms=3, mfc="none", mec="#555555",
            mew=0.6, zorder=4)
    goals = data.goals.sets[-1]  # after the set_goal edits, if any
    if np.isfinite(goals).any():
        ax.plot(goals[:, 0], goals[:, 1], ls="none", marker="x", ms=4, color=GOAL_COLOR,
                zorder=4)
        handles.append(Line2D([], [], ls="none", marker="x", ms=5, color=GOAL_COLOR,
                              label="goal at the end" if data.goals.edited else "goal"))
    end = data.pose[-1]
    for code, (marker, label) in FINAL_MARKS.items():
        chosen = final == code
        if not chosen.any():
            continue
        colour = table[code]
        ax.plot(end[chosen, 0], end[chosen, 1], ls="none", marker=marker, ms=7, color=colour,
                mec="black" if marker != "." else colour, mew=0.5, zorder=5)
        handles.append(Line2D([], [], ls="none", marker=marker, ms=7, color=colour,
                              mec="black" if marker != "." else colour, mew=0.5,
                              label=f"{label} ({int(chosen.sum())})"))
    stars = _livelock_points(data)
    if len(stars):
        ax.plot(stars[:, 0], stars[:, 1], ls="none", marker="*", ms=10,
                color=STATUS_COLORS["livelock"], mec="black", mew=0.4, zorder=6)
        handles.append(Line2D([], [], ls="none", marker="*", ms=10,
                              color=STATUS_COLORS["livelock"], mec="black", mew=0.4,
                              label=f"livelock detected ({len(stars)})"))
    pad_x, pad_y = 0.02 * (xmax - xmin), 0.02 * (ymax - ymin)
    ax.set_xlim(xmin - pad_x, xmax + pad_x)
    ax.set_ylim(ymin - pad_y, ymax + pad_y)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    summary = getattr(loaded, "summary", {}) or {}
    status = summary.get("status", "")
    ax.set_title(f"{data.title}: {status}, {data.duration:g} s simulated, {data.n} robots"
                 if status else data.title, fontsize=10)
    fig.legend(handles=handles, loc="outside right upper", fontsize=8, frameon=False)
    return _save(fig, out)


def _draw_walls(ax: Any, data: Any) -> list[Any]:
    """The walls: kept ones black, added ones coloured, removed ones dashed; returns the
    legend's entries for the edited walls (none for a run without wall edits)."""
    sets = data.walls.sets
    final = sets[-1]
    if len(sets) == 1:
        ax.add_collection(LineCollection(final.reshape(-1, 2, 2), colors=WALL_COLOR,
                                         linewidths=1.5, zorder=2))
        return []
    start_rows = {tuple(row) for row in sets[0].tolist()}
    final_rows = {tuple(row) for row in final.tolist()}
    kept = [row for row in final.tolist() if tuple(row) in start_rows]
    added = [row for row in final.tolist() if tuple(row) not in start_rows]
    removed: list[list[float]] = []  # every wall shown at some step but not at the end
    seen: set[tuple[float, ...]] = set()
    for walls in sets[:-1]:
        for row in walls.tolist():
            if tuple(row) not in final_rows and tuple(row) not in seen:
                seen.add(tuple(row))
                removed.append(row)
    handles: list[Any] = []
    for rows, colour, style, label in (
            (kept, WALL_COLOR, "-", None),
            (removed, REMOVED_WALL_COLOR, "--", "wall removed by an edit"),
            (added, ADDED_WALL_COLOR, "-", "wall added by an edit")):
        if not rows:
            continue
        ax.add_collection(LineCollection(np.array(rows).reshape(-1, 2, 2), colors=colour,
                                         linewidths=1.5, linestyles=style, zorder=2,
                                         label=label))
        if label is not None:
            handles.append(Line2D([], [], color=colour, lw=1.5, ls=style,
                                  label=f"{label} ({len(rows)})"))
    return handles


def _livelock_points(data: Any) -> np.ndarray:
    """Positions where a livelock started (rising edges of the livelock mask)."""
    mask = data.livelock
    rising = mask & ~np.vstack([np.zeros((1, mask.shape[1]), dtype=bool), mask[:-1]])
    k, r = np.nonzero(rising)
    return data.pose[k, r, :2].astype(np.float64)
