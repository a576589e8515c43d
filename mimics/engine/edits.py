"""Edits of a running world (``mimics.world.edits``), applied at a step boundary.

A part of ``mimics.engine.simulation.Simulation`` kept on its own, as
``deactivations.py`` is: ``WorldEdits.edit`` applies an edit now, between
two steps (the workbench's live view); the edits a scenario schedules
(``scenario.edits``) are applied by the simulation itself at the top of the
step whose number they carry, which is the same point of the run: after step
``k`` has ended (its observers called) and before the robots act again. A
live edit joins the run's timeline of edits (``sim.scenario.edits``), so the
scenario recorded at the end re-runs the edited run bit for bit.

An edit that would put a robot inside a wall or another robot (the engine's
own collision test, ``collision.find_collisions``), a robot that does not
exist or was removed, a position or goal off the map or a goal in a wall is
refused with one ``mimics.world.edits.EditError`` line; nothing
changes then. After an edit the robots' sensors read the edited world: the
ranger's scan and the positioning of this step are taken again (the same
noise: it is keyed by step), the robots' index and, for walls, the walls'
grids are rebuilt.

A run ended from outside at a step boundary (``WorldEdits.end``: the
workbench's Stop, a wall limit that passed while paused) joins that timeline
too, as an ``end`` edit: the recorded scenario then re-runs to the same end,
status and digest included, rather than to its time limit.

>>> from mimics.algorithms import go_to_goal
>>> from mimics.scenarios.line import scenario
>>> from mimics.engine.simulation import Simulation
>>> sim = Simulation(scenario(robots=2), go_to_goal, seed=1, time_limit=2.0)
>>> sim.edit({"kind": "set_goal", "robot": 1, "x": 5.0, "y": 2.0}).describe()
"step 0 (t = 0 s): set robot 1's goal to (5, 2)"
>>> sim.edit({"kind": "move_robot", "robot": 0, "x": 0.0, "y": 2.0})
Traceback (most recent call last):
...
mimics.world.edits.EditError: edit: robot 0 at (0, 2) would overlap robot 1
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.collision import Bodies, find_collisions
from mimics.engine.outcome import Event
from mimics.engine.ranging import WallIndex, shared_wall_index
from mimics.engine.sensors import measure_positioning
from mimics.engine.spatial_index import as_segments, build_segment_grid
from mimics.engine.state import Status
from mimics.world.edits import (
    END_STATUSES,
    REMOVE_REACH,
    Edit,
    EditError,
    check_edit_coordinates,
    edit_from_dict,
    nearest_wall,
)
from mimics.world.maps import Map

if TYPE_CHECKING:
    from mimics.engine.ranging import Scanner
    from mimics.engine.spatial_index import SegmentGrid
    from mimics.engine.state import TypeArrays, WorldState
    from mimics.world.scenario import Scenario

_REMOVED = int(Status.REMOVED)


@dataclass(frozen=True)
class AppliedEdit:
    """An edit as applied: resolved (``remove_wall`` by its index), with its step and time.

    Attributes:
        edit: the edit, its ``step`` the step boundary it was applied at.
        time: the simulated time then (s).
    """

    edit: Edit
    time: float

    @property
    def step(self) -> int:
        """The step boundary it was applied at (after this many steps)."""
        return self.edit.step

    def describe(self) -> str:
        """``step 40 (t = 4 s): add wall segment [...]``."""
        return f"step {self.step} (t = {self.time:g} s): {self.edit.describe()}"

    def to_dict(self) -> dict[str, Any]:
        """Plain data: the edit's fields, ``time`` and ``detail`` (its short description)."""
        return {**self.edit.to_dict(), "time": round(self.time, 9),
                "detail": self.edit.describe()}


class WorldEdits:
    """The Simulation's edits of its world (a mixin of its state)."""

    scenario: Scenario
    state: WorldState
    types: TypeArrays
    status: str
    events: list[Event]
    observers: list[Any]
    noise: dict[str, Any]
    wall_grid: SegmentGrid
    _scanner: Scanner
    _grid_key: tuple[int, bytes] | None
    _comms: np.ndarray | None

    def _start_edits(self, scenario: Scenario) -> None:
        """The world as the scenario starts it, and its timeline of edits."""
        self.world_map = scenario.map  # the walls as edited so far (the scenario keeps the first)
        self._applied_edits = 0  # edits of scenario.edits applied (or refused) so far
        self.wall_grid = build_segment_grid(as_segments(scenario.map.segments),
                                            scenario.map.bounds)

    @cached_property
    def walls(self) -> WallIndex:
        """The walls indexed for the ranger (built when a scan is first traced)."""
        world = self.world_map
        return shared_wall_index(world.segments, world.bounds,
                                 float(np.max(self.types.max_range, initial=0.0)),
                                 grid=self.wall_grid)

    def edit(self, edit: Edit | Mapping[str, Any]) -> AppliedEdit:
        """Apply ``edit`` now, at this step boundary (its ``step``, if any, is replaced by
        the current step), and add it to the run's edits (``scenario.edits``).

        Raises:
            EditError: one line, when the edit is malformed or refused (nothing changed).
        """
        if not isinstance(edit, Edit):
            edit = edit_from_dict(edit, bounds=self.world_map.bounds)
        if not self._started:  # type: ignore[attr-defined]
            self.start()  # type: ignore[attr-defined]
        if self.status != "running":
            raise EditError(f"edit: the run has ended ({self.status}); nothing to edit")
        edit = edit.at_step(self.state.step)
        if edit.kind == "end":
            self.end(edit.status or "stopped")
            return AppliedEdit(edit, self.state.time)
        applied = self._apply_edit(edit, "edit")
        timeline = list(self.scenario.edits)
        timeline.insert(self._applied_edits, applied.edit)  # before those still to come
        self._applied_edits += 1
        self.scenario = replace(self.scenario, edits=tuple(timeline))
        self._after_edits()
        return applied

    def end(self, status: str = "stopped") -> None:
        """End the run now, at this step boundary, with ``status`` (``stopped`` or
        ``wall_limit``; observers' ``on_end`` are called), and record the end in the run's
        timeline of edits (:meth:`record_end`). Nothing happens once the run has ended.

        Raises:
            EditError: for another status.
        """
        if status not in END_STATUSES:
            raise EditError(f"end: expected a status of {', '.join(END_STATUSES)}, got "
                            f"{status!r}")
        if not self._started:  # type: ignore[attr-defined]
            self.start()  # type: ignore[attr-defined]
        if self.status != "running":
            return
        self.status = status
        self.record_end()
        self._check_end()  # type: ignore[attr-defined]

    def record_end(self) -> None:
        """Add the run's end (its step and status) to its timeline of edits
        (``scenario.edits``), so that the scenario re-runs to the same end: for an end the
        engine does not reach by itself (``stopped`` from outside, ``wall_limit``). Once
        only; an end the timeline already holds (a re-run) is not added again."""
        if self.status not in END_STATUSES:
            return
        timeline = list(self.scenario.edits)
        done = timeline[:self._applied_edits]
        if done and done[-1].kind == "end":
            return
        timeline.insert(self._applied_edits, Edit("end", self.state.step, status=self.status))
        self._applied_edits += 1
        self.scenario = replace(self.scenario, edits=tuple(timeline))

    def _apply_due_edits(self) -> bool:
        """Apply the scenario's edits due at this step (a refused one becomes an
        ``edit_refused`` event); returns False if the run ended (no robot left, or an
        ``end`` edit)."""
        edits = self.scenario.edits
        step = self.state.step
        changed = False
        while self._applied_edits < len(edits) and edits[self._applied_edits].step <= step:
            edit = edits[self._applied_edits]
            self._applied_edits += 1
            if edit.kind == "end":  # a recorded end: the run ends as it did
                if changed and not self._after_edits():
                    return False  # an edit before it removed the last robot
                self.status = edit.status or "stopped"
                return self._check_end()  # type: ignore[attr-defined,no-any-return]
            try:
                self._apply_edit(edit.at_step(step), f"edits[{self._applied_edits - 1}]")
            except EditError as refusal:
                self.events.append(Event(self.state.time, -1 if edit.robot is None
                                         else edit.robot, "edit_refused", str(refusal)))
            changed = True
        return self._after_edits() if changed else True

    def _after_edits(self) -> bool:
        """End the run when an edit removed its last active robot; True while it goes on."""
        if self.state.active.any():
            return True
        return self._check_end()  # type: ignore[attr-defined,no-any-return]

    # -- one edit ---------------------------------------------------------------

    def _apply_edit(self, edit: Edit, name: str) -> AppliedEdit:
        """Check ``edit`` against the world now, apply it, take the senses again, record it."""
        state = self.state
        kind = edit.kind
        # (an Edit made in Python or scheduled skips the reader's check of its walls)
        check_edit_coordinates(edit, self.world_map.bounds, name)
        if edit.robot is not None:
            self._check_robot(edit.robot, name)
        if kind == "move_robot":
            self._move_robot(edit, name)
        elif kind == "set_goal":
            self._set_goal(edit, name)
        elif kind == "remove_robot":
            robot = int(edit.robot)  # type: ignore[arg-type]
            state.status[robot] = _REMOVED
            state.deactivation_time[robot] = state.time
            state.velocity[robot] = 0.0
        elif kind == "add_wall":
            self._add_walls(edit, name)
        else:
            edit = self._remove_wall(edit, name)
        applied = AppliedEdit(edit, state.time)
        self._grid_key = None  # poses or the solid robots changed within the step
        self._comms = None
        self._scanner.sense()
        measure_positioning(state, self.types, self.noise)
        self.events.append(Event(state.time, -1 if edit.robot is None else edit.robot, "edit",
                                 edit.describe()))
        for observer in self.observers:
            if hasattr(observer, "on_edit"):
                observer.on_edit(self, applied)
        return applied

    def _check_robot(self, robot: int, name: str) -> None:
        n = self.state.n
        if robot >= n:
            raise EditError(f"{name}.robot: no robot {robot} (the run has {n}: 0 to {n - 1})")
        if self.state.status[robot] == _REMOVED:
            raise EditError(f"{name}.robot: robot {robot} was removed")

    def _check_point(self, x: float, y: float, what: str, name: str) -> None:
        xmin, ymin, xmax, ymax = self.world_map.bounds
        if not (xmin <= x <= xmax and ymin <= y <= ymax):
            raise EditError(f"{name}: {what} ({x:g}, {y:g}) is outside the map bounds "
                            f"({xmin:g}, {ymin:g}, {xmax:g}, {ymax:g})")

    def _solid_now(self) -> np.ndarray:
        return self._solid()  # type: ignore[attr-defined,no-any-return]

    def _move_robot(self, edit: Edit, name: str) -> None:
        state = self.state
        robot, x, y = int(edit.robot), float(edit.x), float(edit.y)  # type: ignore[arg-type]
        self._check_point(x, y, f"robot {robot} at", name)
        yaw = float(state.pose[robot, 2]) if edit.yaw is None else edit.yaw
        pose = state.pose.copy()
        pose[robot] = (x, y, yaw)
        check = np.zeros(state.n, dtype=bool)
        check[robot] = True
        solid = self._solid_now().copy()
        solid[robot] = True
        with_whom, wall = find_collisions(
            Bodies(np.ascontiguousarray(pose[:, :2]), np.ascontiguousarray(pose[:, 2]),
                   self.types.half_length, self.types.half_width),
            check, solid, self.wall_grid)
        if with_whom[robot] >= 0:
            raise EditError(f"{name}: robot {robot} at ({x:g}, {y:g}) would overlap robot "
                            f"{int(with_whom[robot])}")
        if wall[robot] >= 0:
            raise EditError(f"{name}: robot {robot} at ({x:g}, {y:g}) would touch "
                            f"{self._wall_name(int(wall[robot]))}")
        # placed by hand: it stands still, its controllers start afresh
        state.pose[robot] = pose[robot]
        state.odometry[robot] = pose[robot]
        for column in (state.velocity, state.acceleration, state.reference, state.actuation,
                       state.pid_integral):
            column[robot] = 0.0

    def _set_goal(self, edit: Edit, name: str) -> None:
        robot, x, y = int(edit.robot), float(edit.x), float(edit.y)  # type: ignore[arg-type]
        self._check_point(x, y, f"robot {robot}'s goal", name)
        # a goal where the robot, square to the walls, would touch one cannot be reached
        side = np.array([self.types.half_width[robot]])
        _, wall = find_collisions(Bodies(np.array([[x, y]]), np.zeros(1), side, side),
                                  np.ones(1, dtype=bool), np.zeros(1, dtype=bool),
                                  self.wall_grid)
        if wall[0] >= 0:
            raise EditError(f"{name}: robot {robot}'s goal ({x:g}, {y:g}) is in "
                            f"{self._wall_name(int(wall[0]))} (the robot would touch it there)")
        self.state.goal[robot] = (x, y)

    def _add_walls(self, edit: Edit, name: str) -> None:
        state = self.state
        solid = self._solid_now()
        segments = edit.wall_segments()
        if edit.rectangle is not None:  # an obstacle dropped on a robot: it would be inside
            x0, y0, x1, y1 = edit.rectangle
            x, y = state.pose[:, 0], state.pose[:, 1]
            inside = np.flatnonzero(solid & (x0 < x) & (x < x1) & (y0 < y) & (y < y1))
            if inside.size:
                robot = int(inside[0])
                raise EditError(f"{name}: the rectangle would enclose robot {robot} at "
                                f"({x[robot]:g}, {y[robot]:g})")
        grid = build_segment_grid(segments, self.world_map.bounds)
        _, touched = find_collisions(
            Bodies(np.ascontiguousarray(state.pose[:, :2]), np.ascontiguousarray(state.pose[:, 2]),
                   self.types.half_length, self.types.half_width),
            solid, solid, grid)
        inside = np.flatnonzero(touched >= 0)
        if inside.size:
            robot = int(inside[0])
            x, y = state.pose[robot, :2].tolist()
            raise EditError(f"{name}: the wall would touch robot {robot} at ({x:g}, {y:g})")
        self._set_walls(np.vstack([self.world_map.segments, segments]))

    def _remove_wall(self, edit: Edit, name: str) -> Edit:
        segments = self.world_map.segments
        count = len(segments)
        if edit.wall is not None:
            if edit.wall >= count:
                raise EditError(f"{name}.wall: no wall {edit.wall} (the map has {count}"
                                f"{f': 0 to {count - 1}' if count else ''})")
            index = edit.wall
        else:
            found = nearest_wall(segments, edit.at)  # type: ignore[arg-type]
            if found is None:
                px, py = edit.at  # type: ignore[misc]
                raise EditError(f"{name}.at: no wall within {REMOVE_REACH:g} m of "
                                f"({px:g}, {py:g})")
            index = found
        self._set_walls(np.delete(segments, index, axis=0))
        return replace(edit, wall=index, at=None)

    def _set_walls(self, segments: np.ndarray) -> None:
        """Make ``segments`` the walls of the run: the collisions' grid, the ranger's index
        (rebuilt when next scanned) and its sight lists follow."""
        world = self.world_map
        edited = Map(segments, world.bounds, name=world.name, source=world.source)
        # the grid first: should it fail, the run keeps its walls as they were
        self.wall_grid = build_segment_grid(as_segments(edited.segments), world.bounds)
        self.world_map = edited
        self.__dict__.pop("walls", None)
        self._scanner.walls_changed()

    def _wall_name(self, index: int) -> str:
        x1, y1, x2, y2 = self.world_map.segments[index].tolist()
        return f"wall {index} ({x1:g}, {y1:g})-({x2:g}, {y2:g})"

