"""Edits of a running world, as plain data: what changes, and at which step.

An ``Edit`` is one change a user makes to a run while it runs (the
workbench's live view) or schedules in a scenario file (``[[edits]]``
tables): it applies at a step boundary, after ``step`` steps, before the
robots act again. The engine applies it (``mimics.engine.edits``); here it is
only read and checked on its own (kinds, fields, numbers), each mistake one
``EditError`` line naming the field.

Kinds and their fields (positions in m, angles in rad):

================ ==============================================================
kind             fields
================ ==============================================================
``move_robot``   ``robot``, ``x``, ``y``, optional ``yaw`` (default: keep the
                 heading); the robot stands still afterwards (velocity reset)
``add_wall``     ``segment = [x1, y1, x2, y2]`` or ``rectangle = [xmin, ymin,
                 xmax, ymax]`` (its four sides)
``remove_wall``  ``wall`` (index in the run's current wall list) or ``at =
                 [x, y]`` (the wall nearest that point, within ``REMOVE_REACH``)
``set_goal``     ``robot``, ``x``, ``y``
``remove_robot`` ``robot``
``end``          ``status`` (``stopped`` or ``wall_limit``): the run ends there
                 with that status, as a live run that was stopped (or whose wall
                 limit passed) ended: its record re-runs to the same end
================ ==============================================================

Every kind also takes ``step`` (a whole number >= 0, default 0).

>>> edit = edit_from_dict({"kind": "add_wall", "step": 40, "rectangle": [1, 1, 2, 3]})
>>> edit.wall_segments().tolist()
[[1.0, 1.0, 2.0, 1.0], [2.0, 1.0, 2.0, 3.0], [2.0, 3.0, 1.0, 3.0], [1.0, 3.0, 1.0, 1.0]]
>>> edit.describe()
'add wall rectangle [1, 1, 2, 3]'
>>> edit_from_dict({"kind": "move_robot", "robot": 0, "x": "abc", "y": 1})
Traceback (most recent call last):
...
mimics.world.edits.EditError: edit.x: expected a number, got 'abc'
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from mimics.world.errors import MimicsError, ScenarioError
from mimics.world.limits import MAX_ROBOTS, MAX_STEPS, check_coordinates

EDIT_KINDS = ("move_robot", "add_wall", "remove_wall", "set_goal", "remove_robot", "end")
#: How a recorded ``end`` ends the run (the ends the engine does not reach by itself).
END_STATUSES = ("stopped", "wall_limit")
#: The fields each kind takes besides ``kind`` and ``step``: (required, optional).
KIND_FIELDS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "move_robot": (("robot", "x", "y"), ("yaw",)),
    "add_wall": ((), ("segment", "rectangle")),
    "remove_wall": ((), ("wall", "at")),
    "set_goal": (("robot", "x", "y"), ()),
    "remove_robot": (("robot",), ()),
    "end": (("status",), ()),
}
#: ``remove_wall`` with ``at``: the nearest wall must be at most this far from the point (m).
REMOVE_REACH = 1.0
MAX_WALL_INDEX = 100_000_000


class EditError(ScenarioError):
    """An edit is malformed, or refused by the running world (one line naming why)."""


@dataclass(frozen=True)
class Edit:
    """One change to a running world at a step boundary (fields unused by a kind are None).

    Attributes:
        kind: one of ``EDIT_KINDS``.
        step: applied after this many steps (0: before the first).
        robot: the robot moved, given a goal or removed.
        x, y: the new position (``move_robot``) or goal (``set_goal``).
        yaw: the new heading (``move_robot``; None keeps the heading).
        segment: ``add_wall``'s one wall ``(x1, y1, x2, y2)``.
        rectangle: ``add_wall``'s rectangle ``(xmin, ymin, xmax, ymax)``.
        wall: ``remove_wall``'s index in the current wall list.
        at: ``remove_wall``'s point, near the wall to remove.
        status: ``end``'s status (one of ``END_STATUSES``).
    """

    kind: str
    step: int = 0
    robot: int | None = None
    x: float | None = None
    y: float | None = None
    yaw: float | None = None
    segment: tuple[float, float, float, float] | None = None
    rectangle: tuple[float, float, float, float] | None = None
    wall: int | None = None
    at: tuple[float, float] | None = None
    status: str | None = None

    def wall_segments(self) -> np.ndarray:
        """``add_wall``'s walls, ``(k, 4)``: the segment, or the rectangle's four sides
        (counter-clockwise from its lower left corner)."""
        if self.segment is not None:
            return np.array([self.segment], dtype=np.float64)
        if self.rectangle is None:
            return np.zeros((0, 4))
        x0, y0, x1, y1 = self.rectangle
        return np.array([[x0, y0, x1, y0], [x1, y0, x1, y1], [x1, y1, x0, y1], [x0, y1, x0, y0]],
                        dtype=np.float64)

    def at_step(self, step: int) -> Edit:
        """This edit applied after ``step`` steps instead."""
        return replace(self, step=step)

    def to_dict(self) -> dict[str, Any]:
        """The edit as plain data (what ``edit_from_dict`` reads back): ``step``,
        ``kind``, then the fields set, in the table's order."""
        data: dict[str, Any] = {"step": self.step, "kind": self.kind}
        for name in ("robot", "x", "y", "yaw", "segment", "rectangle", "wall", "at",
                     "status"):
            value = getattr(self, name)
            if value is not None:
                data[name] = list(value) if isinstance(value, tuple) else value
        return data

    def describe(self) -> str:
        """A short readable line: ``move robot 3 to (1.5, 2, yaw 0.3)``."""
        kind = self.kind
        if kind == "move_robot":
            heading = "" if self.yaw is None else f", yaw {self.yaw:g}"
            return f"move robot {self.robot} to ({self.x:g}, {self.y:g}{heading})"
        if kind == "set_goal":
            return f"set robot {self.robot}'s goal to ({self.x:g}, {self.y:g})"
        if kind == "remove_robot":
            return f"remove robot {self.robot}"
        if kind == "end":
            return f"end the run ({self.status})"
        if kind == "add_wall":
            shape, values = (("segment", self.segment) if self.segment is not None
                             else ("rectangle", self.rectangle))
            return f"add wall {shape} [{', '.join(f'{v:g}' for v in values or ())}]"
        if self.wall is not None:
            return f"remove wall {self.wall}"
        ax, ay = self.at or (math.nan, math.nan)
        return f"remove the wall nearest ({ax:g}, {ay:g})"


def edit_from_dict(data: Mapping[str, Any], where: str = "edit", *,
                   default_step: int = 0, bounds: tuple[float, ...] | None = None) -> Edit:
    """Read one edit from plain data (a TOML table, a JSON body), strictly.

    Args:
        data: ``kind``, optional ``step`` and the kind's fields (module docstring).
        where: what names the edit in errors (``edit``, ``file.toml, line 12: edits[0]``).
        default_step: the step when ``data`` gives none.
        bounds: the map's bounds, when known: walls and points are then checked to lie
            within them plus a margin (``check_edit_coordinates``).

    Raises:
        EditError: ``{where}.{field}: expected ..., got ...`` for the first mistake.
    """
    if not isinstance(data, Mapping):
        raise EditError(f"{where}: expected a table with a kind, got {data!r}")
    kind = data.get("kind")
    if kind not in EDIT_KINDS:
        got = "nothing" if kind is None else repr(kind)
        raise EditError(f"{where}.kind: expected one of {', '.join(EDIT_KINDS)}, got {got}")
    required, optional = KIND_FIELDS[kind]
    allowed = ("kind", "step", *required, *optional)
    for name in data:
        if name not in allowed:
            raise EditError(f"{where}.{name}: unknown field for {kind} (expected one of "
                            f"{', '.join(allowed)})")
    for name in required:
        if name not in data:
            raise EditError(f"{where}: missing field {name!r} for {kind}")
    step = _whole(data.get("step", default_step), f"{where}.step", MAX_STEPS)
    fields: dict[str, Any] = {}
    for name in ("x", "y", "yaw"):
        if name in data:
            fields[name] = _number(data[name], f"{where}.{name}")
    if "robot" in data:
        fields["robot"] = _whole(data["robot"], f"{where}.robot", MAX_ROBOTS - 1)
    if kind in ("add_wall", "remove_wall"):
        pair = optional
        given = [name for name in pair if name in data]
        if len(given) != 1:
            raise EditError(f"{where}: expected exactly one of {' or '.join(pair)} for {kind}, "
                            f"got {' and '.join(given) or 'neither'}")
    if "segment" in data:
        segment = _numbers(data["segment"], f"{where}.segment", 4, "[x1, y1, x2, y2]")
        if segment[:2] == segment[2:]:
            raise EditError(f"{where}.segment: expected two different ends, got "
                            f"{list(segment)}")
        fields["segment"] = segment
    if "rectangle" in data:
        box = _numbers(data["rectangle"], f"{where}.rectangle", 4, "[xmin, ymin, xmax, ymax]")
        if not (box[0] < box[2] and box[1] < box[3]):
            raise EditError(f"{where}.rectangle: expected xmin < xmax and ymin < ymax, got "
                            f"{list(box)}")
        fields["rectangle"] = box
    if "wall" in data:
        fields["wall"] = _whole(data["wall"], f"{where}.wall", MAX_WALL_INDEX)
    if "at" in data:
        fields["at"] = _numbers(data["at"], f"{where}.at", 2, "[x, y]")
    if "status" in data:
        if data["status"] not in END_STATUSES:
            raise EditError(f"{where}.status: expected one of {', '.join(END_STATUSES)}, got "
                            f"{data['status']!r}")
        fields["status"] = data["status"]
    edit = Edit(kind=kind, step=step, **fields)
    if bounds is not None:
        check_edit_coordinates(edit, bounds, where)
    return edit


def check_edit_coordinates(edit: Edit, bounds: tuple[float, ...], where: str) -> None:
    """Refuse an edit's wall or point outside the map's bounds plus a margin
    (``mimics.world.limits.coordinate_limits``): finite but enormous coordinates would
    overflow the walls' grids far from the input. Positions and goals (``x``, ``y``) are
    held to the bounds themselves where the edit is applied.

    Raises:
        EditError: naming the field (``edit.segment``) and the allowed ranges.
    """
    for name in ("segment", "rectangle", "at"):
        value = getattr(edit, name)
        if value is not None:
            try:
                check_coordinates(f"{where}.{name}", value, bounds)
            except MimicsError as exc:
                raise EditError(str(exc)) from None


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise EditError(f"{where}: expected a number, got {value!r}")
    return float(value)


def _whole(value: Any, where: str, maximum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise EditError(f"{where}: expected a whole number >= 0, got {value!r}")
    if value > maximum:
        raise EditError(f"{where}: {value} is over the limit of {maximum}")
    return int(value)


def _numbers(value: Any, where: str, size: int, shape: str) -> tuple[Any, ...]:
    if (not isinstance(value, list | tuple) or len(value) != size
            or any(isinstance(v, bool) or not isinstance(v, int | float) or not math.isfinite(v)
                   for v in value)):
        raise EditError(f"{where}: expected {shape}, got {value!r}")
    return tuple(float(v) for v in value)


def check_edit_fits(edit: Edit, robots: int, bounds: tuple[float, ...], name: str) -> None:
    """Check what can be checked against a scenario before it runs: a robot index that
    exists, a position or goal inside the map bounds, walls and points within them plus
    a margin (``name``: the edit in errors).

    Raises:
        EditError: naming the edit's field (``edits[2].robot``) and what was expected.
    """
    xmin, ymin, xmax, ymax = bounds
    check_edit_coordinates(edit, bounds, name)
    if edit.robot is not None and edit.robot >= robots:
        raise EditError(f"{name}.robot: no robot {edit.robot} (the scenario has {robots}: "
                        f"0 to {robots - 1})")
    if edit.x is not None and edit.y is not None and not (
            xmin <= edit.x <= xmax and ymin <= edit.y <= ymax):
        raise EditError(f"{name}: ({edit.x:g}, {edit.y:g}) is outside the map bounds "
                        f"({xmin:g}, {ymin:g}, {xmax:g}, {ymax:g})")


def point_segment_distances(px: float, py: float, segments: np.ndarray) -> np.ndarray:
    """Distance from the point ``(px, py)`` to each segment of ``segments`` ``(m, 4)``."""
    segments = np.asarray(segments, dtype=np.float64).reshape(-1, 4)
    start, along = segments[:, :2], segments[:, 2:] - segments[:, :2]
    length2 = np.einsum("ij,ij->i", along, along)
    point = np.array([px, py])
    t = np.clip(np.einsum("ij,ij->i", point - start, along) / np.maximum(length2, 1e-300),
                0.0, 1.0)
    return np.hypot(*(start + t[:, None] * along - point).T)


def nearest_wall(segments: np.ndarray, at: tuple[float, float]) -> int | None:
    """``remove_wall``'s wall for the point ``at``: the nearest within ``REMOVE_REACH``
    (the lowest index at equal distance), or None."""
    if not len(segments):
        return None
    distance = point_segment_distances(at[0], at[1], segments)
    index = int(np.argmin(distance))
    return index if distance[index] <= REMOVE_REACH else None


def walls_after(segments: np.ndarray, edits: Iterable[Edit], step: int | None = None
                ) -> np.ndarray:
    """The walls once the wall edits among ``edits`` up to ``step`` (None: all) are applied
    in order, as a run applies them: added walls appended, a removed one taken out by
    its index (or nearest its point). For drawing an edited run's walls at a step (a
    replay); an edit a run refused (an ``edit_refused`` event) is assumed applied.

    >>> walls = np.array([[0.0, 0.0, 1.0, 0.0]])
    >>> edits = [Edit("add_wall", 5, segment=(2.0, 0.0, 2.0, 1.0)), Edit("remove_wall", 9, wall=0)]
    >>> walls_after(walls, edits, step=5).tolist()
    [[0.0, 0.0, 1.0, 0.0], [2.0, 0.0, 2.0, 1.0]]
    >>> walls_after(walls, edits).tolist()
    [[2.0, 0.0, 2.0, 1.0]]
    """
    walls = np.asarray(segments, dtype=np.float64).reshape(-1, 4)
    for edit in edits:
        if step is not None and edit.step > step:
            break
        if edit.kind == "add_wall":
            walls = np.vstack([walls, edit.wall_segments()])
        elif edit.kind == "remove_wall":
            index = edit.wall if edit.at is None else nearest_wall(walls, edit.at)
            if index is not None and index < len(walls):
                walls = np.delete(walls, index, axis=0)
    return walls
