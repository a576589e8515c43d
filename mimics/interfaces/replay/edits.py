"""What a run's edits change in its replay: the walls and the goals at each recorded step,
and the jumps of the robots an edit moved (their trails are broken there, not drawn across
the jump).

An edit at step ``s`` applies after ``s`` steps (``mimics.world.edits``): the walls
shown at a frame of step ``f`` are those after the edits of steps ``<= f`` (what
the robots sensed when they chose their next move, and what the live view shows
when paused there). A robot moved at step ``s`` is at its old place in the frame
of step ``s`` and at the new one from the next recorded frame on. A timed edit the
run refused (an ``edit_refused`` event naming ``edits[k]``) changed nothing and is
left out.

>>> import numpy as np
>>> from mimics.world.edits import Edit
>>> timeline = wall_timeline(np.array([[0.0, 0.0, 1.0, 0.0]]),
...                          [Edit("add_wall", 5, segment=(2.0, 0.0, 2.0, 1.0)),
...                           Edit("remove_wall", 9, wall=0)])
>>> timeline.steps.tolist(), [len(walls) for walls in timeline.sets]
([0, 5, 9], [1, 2, 1])
>>> timeline.set_at(np.array([0, 4, 5, 8, 9, 30])).tolist()
[0, 0, 1, 1, 2, 2]
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from mimics.world.edits import Edit, walls_after

_REFUSED = re.compile(r"^edits\[(\d+)\]")  # an edit_refused event names the timed edit


@dataclass(frozen=True)
class Timeline:
    """Something an edit changes (the walls, the goals), over a run's steps.

    Attributes:
        steps: ``(k,)`` increasing steps; set ``j`` is shown from step ``steps[j]`` on
            (``steps[0]`` is 0, the world as the run started).
        sets: the ``k`` sets: walls ``(m_j, 4)``, or goals ``(n, 2)``.
    """

    steps: np.ndarray
    sets: tuple[np.ndarray, ...]

    def set_at(self, steps: np.ndarray | int) -> np.ndarray:
        """The index of the wall set shown at each of ``steps``."""
        index = np.searchsorted(self.steps, np.asarray(steps), side="right") - 1
        return np.maximum(index, 0)

    @property
    def edited(self) -> bool:
        """True when an edit changed them."""
        return len(self.sets) > 1


def applied_edits(edits: Sequence[Edit], events: Any = None) -> list[Edit]:
    """``edits`` (a scenario's timeline) without those the run refused, as named by its
    ``edit_refused`` events (``events``: a table with ``kind`` and ``detail``, or None)."""
    refused: set[int] = set()
    if events is not None and len(events) and "kind" in getattr(events, "columns", ()):
        rows = events[events["kind"] == "edit_refused"]
        for detail in rows["detail"]:
            found = _REFUSED.match(str(detail))
            if found:
                refused.add(int(found.group(1)))
    return [edit for k, edit in enumerate(edits) if k not in refused]


def wall_timeline(segments: np.ndarray, edits: Iterable[Edit]) -> Timeline:
    """The wall sets of a run that starts with ``segments`` and applies ``edits`` (its
    applied edits, in order): one set per step where a wall edit applies."""
    edits = list(edits)
    start = np.asarray(segments, dtype=np.float64).reshape(-1, 4)
    steps = [0]
    sets = [start]
    for step in sorted({e.step for e in edits if e.kind in ("add_wall", "remove_wall")}):
        walls = walls_after(start, edits, step)
        if step == 0:
            sets[0] = walls
        else:
            steps.append(step)
            sets.append(walls)
    return Timeline(np.array(steps, dtype=np.int64), tuple(sets))


def goal_timeline(goals: np.ndarray, edits: Iterable[Edit]) -> Timeline:
    """The goals ``(n, 2)`` of a run that starts with ``goals`` and applies ``edits``: one
    set per step where a ``set_goal`` edit applies."""
    current = np.asarray(goals, dtype=np.float64).reshape(-1, 2).copy()
    steps, sets = [0], [current]
    for edit in edits:
        if edit.kind != "set_goal" or edit.robot is None or edit.robot >= len(current):
            continue
        if edit.step != steps[-1]:
            current = current.copy()
            steps.append(edit.step)
            sets.append(current)
        current[edit.robot] = (edit.x, edit.y)
    return Timeline(np.array(steps, dtype=np.int64), tuple(sets))


def robot_moves(edits: Iterable[Edit]) -> dict[int, np.ndarray]:
    """The steps at which each robot was moved by an edit (robot -> sorted steps)."""
    moves: dict[int, list[int]] = {}
    for edit in edits:
        if edit.kind == "move_robot" and edit.robot is not None:
            moves.setdefault(int(edit.robot), []).append(int(edit.step))
    return {robot: np.array(sorted(steps), dtype=np.int64) for robot, steps in moves.items()}


def break_at_moves(path: np.ndarray, steps: np.ndarray, moved_at: np.ndarray) -> np.ndarray:
    """A robot's positions ``(k, 2)`` at the recorded ``steps`` with a NaN row between the
    last point at or before each move step and the first after it (a line drawn through it
    breaks there instead of crossing the jump)."""
    cut = np.unique(np.searchsorted(steps, moved_at, side="right"))
    cut = cut[(cut > 0) & (cut < len(steps))]
    if cut.size == 0:
        return path
    return np.insert(np.asarray(path, dtype=np.float64), cut, np.nan, axis=0)
