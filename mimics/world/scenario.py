"""Scenarios: a map, robot types, and each robot's type, initial stage and goal.

The paper's matrix form, one row ``[x, y, yaw, v, x_goal, y_goal]`` per robot,
is accepted as is:

>>> import numpy as np
>>> from mimics.world.maps import Map
>>> from mimics.world.robot_types import PIONEER_3AT
>>> rows = [[0.0, 1.0 * i, 0.0, 0.0, 20.0, 1.0 * i] for i in range(1, 4)]
>>> s = Scenario.from_matrix(rows, Map.empty((-5, -5, 30, 10)), PIONEER_3AT)
>>> s.robot_count, s.goals[0].tolist()
(3, [20.0, 1.0])
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from typing import Any

import numpy as np

from mimics.world.edits import Edit, check_edit_fits
from mimics.world.errors import ScenarioError
from mimics.world.limits import MAX_MAP_COORDINATE, MAX_ROBOTS, MAX_STEPS
from mimics.world.maps import Map
from mimics.world.robot_types import RobotType

NOISE_CHOICES = ("on", "off")
#: What a collision does to a robot: "deactivate" it (status collided, the paper's rule)
#: or "stall" it, as Stage does: its move is undone and it stays active.
ON_COLLISION_CHOICES = ("deactivate", "stall")
#: What a collision does to a robot: "deactivate" it (status collided, the paper's
#: rule) or "stall" it, as Stage does: its move is undone and it stays active.
ON_COLLISION_CHOICES = ("deactivate", "stall")


@dataclass(frozen=True)
class Settings:
    """Simulation settings a scenario carries (all times in simulated seconds)."""

    dt: float = 0.1
    time_limit: float = 60.0
    goal_tolerance: float = 0.2  # m from the goal counts as reached
    deadlock_distance: float = 0.05  # m moved at most over the window...
    deadlock_window: float = 10.0  # ...to be in deadlock
    deactivate_on_deadlock: bool = True
    livelock_window: float = 30.0  # no progress toward the goal over this window...
    livelock_progress: float = 0.1  # ...of at least this many metres, while moving
    comm_range: float = math.inf  # m; robots farther apart do not see each other in comms
    inactive_as_obstacles: bool = True  # deactivated robots stay in place as obstacles
    allow_overlap: bool = False  # keep robots that start touching a wall or each other
    noise: str = "on"  # "off": every sensor exact, whatever the robot types' noise figures
    on_collision: str = "deactivate"  # or "stall": the move is undone, the robot stays active

    def __post_init__(self) -> None:
        positive = ("dt", "time_limit", "goal_tolerance", "deadlock_window", "livelock_window")
        for name in positive:
            value = getattr(self, name)
            if not _is_number(value) or not 0 < value < math.inf:
                raise ScenarioError(f"settings.{name}: expected a positive number (finite), "
                                    f"got {value!r}")
        for name in ("deadlock_distance", "livelock_progress", "comm_range"):
            value = getattr(self, name)
            finite = name != "comm_range"  # an infinite range means no limit
            if not _is_number(value) or value < 0 or (finite and value == math.inf):
                raise ScenarioError(f"settings.{name}: expected a number >= 0"
                                    f"{' (finite)' if finite else ''}, got {value!r}")
        for name in ("deactivate_on_deadlock", "inactive_as_obstacles", "allow_overlap"):
            if not isinstance(getattr(self, name), bool):
                raise ScenarioError(f"settings.{name}: expected true or false")
        if self.noise not in NOISE_CHOICES:
            raise ScenarioError(f"settings.noise: expected one of {', '.join(NOISE_CHOICES)}, "
                                f"got {self.noise!r}")
        if self.on_collision not in ON_COLLISION_CHOICES:
            raise ScenarioError(f"settings.on_collision: expected one of "
                                f"{', '.join(ON_COLLISION_CHOICES)}, got {self.on_collision!r}")
        if self.time_limit / self.dt > MAX_STEPS:
            raise ScenarioError(f"settings.time_limit: {self.time_limit:g} s at dt = {self.dt:g} "
                                f"s is over the limit of {MAX_STEPS} steps (expected at most "
                                f"{MAX_STEPS * self.dt:.6g} s)")

    @classmethod
    def from_dict(cls, data: dict[str, Any], where: str = "settings") -> Settings:
        """Build settings from a dict, rejecting unknown keys."""
        known = {f.name for f in fields(cls)}
        for key in data:
            if key not in known:
                raise ScenarioError(f"{where}: unknown key {key!r} (expected one of "
                                    f"{', '.join(sorted(known))})")
        return cls(**data)


def _is_number(value: object) -> bool:
    return isinstance(value, int | float) and not isinstance(value, bool) and not math.isnan(value)


@dataclass(frozen=True, eq=False)
class Scenario:
    """Everything needed to start a simulation except the algorithm and the seed.

    Attributes:
        map: walls and bounds.
        types: robot types used, in order; ``type_index[i]`` picks robot i's.
        stages: ``(n, 4)`` initial ``[x, y, yaw, v]`` per robot.
        goals: ``(n, 2)`` goal per robot; a row of NaN means no goal.
        settings: time step, limits and detection thresholds.
        edits: changes to the world at given steps (``mimics.world.edits``), in the
            order they apply (sorted by step, stably).
    """

    map: Map
    types: tuple[RobotType, ...]
    type_index: np.ndarray
    stages: np.ndarray
    goals: np.ndarray
    settings: Settings = field(default_factory=Settings)
    name: str = "scenario"
    parameters: dict[str, Any] = field(default_factory=dict)
    edits: tuple[Edit, ...] = ()

    def __post_init__(self) -> None:
        stages = np.array(self.stages, dtype=np.float64).reshape(-1, 4)
        n = len(stages)
        goals = np.array(self.goals, dtype=np.float64)
        if goals.size == 0 and n:
            goals = np.full((n, 2), np.nan)
        goals = goals.reshape(-1, 2)
        type_index = np.asarray(self.type_index, dtype=np.int64).reshape(-1)
        if n == 0:
            raise ScenarioError(f"scenario {self.name!r}: it has no robots (expected at least 1)")
        if n > MAX_ROBOTS:
            raise ScenarioError(f"scenario {self.name!r}: {n} robots, over the limit of "
                                f"{MAX_ROBOTS}")
        if len(goals) != n or len(type_index) != n:
            raise ScenarioError(f"scenario {self.name!r}: {n} stages, {len(goals)} goals and "
                                f"{len(type_index)} type indices (expected one each per robot)")
        if not self.types:
            raise ScenarioError(f"scenario {self.name!r}: no robot types")
        if type_index.min() < 0 or type_index.max() >= len(self.types):
            raise ScenarioError(f"scenario {self.name!r}: a type index is outside 0.."
                                f"{len(self.types) - 1}")
        bad = np.flatnonzero(~np.all(np.isfinite(stages), axis=1))
        if bad.size:
            raise ScenarioError(f"scenario {self.name!r}: robot {bad[0]} has a non-finite stage "
                                f"{stages[bad[0]].tolist()}")
        for what, values in (("start", stages[:, :2]), ("goal", goals)):
            far = np.flatnonzero(np.nanmax(np.abs(values), axis=1, initial=0.0)
                                 > MAX_MAP_COORDINATE)
            if far.size:  # 1e300 is finite, and breaks every grid and float downstream
                raise ScenarioError(
                    f"scenario {self.name!r}: robot {far[0]}'s {what} "
                    f"{values[far[0]].tolist()} is farther than {MAX_MAP_COORDINATE:g} m from "
                    "the origin (expected coordinates within the limits of a map)")
        yaw = stages[:, 2]
        outside = np.abs(yaw) > np.pi
        if outside.any():  # headings in [-pi, pi] from step 0; those in it stay bit for bit
            stages[outside, 2] = (yaw[outside] + np.pi) % (2 * np.pi) - np.pi
        half_goal = np.isnan(goals).sum(axis=1) == 1
        if half_goal.any():
            i = int(np.flatnonzero(half_goal)[0])
            raise ScenarioError(f"scenario {self.name!r}: robot {i} has a half-defined goal "
                                f"{goals[i].tolist()} (give both x and y, or neither)")
        edits = tuple(sorted(self.edits, key=lambda edit: edit.step))
        for k, edit in enumerate(edits):
            check_edit_fits(edit, n, self.map.bounds, f"scenario {self.name!r}: edits[{k}]")
        for arr in (stages, goals, type_index):
            arr.setflags(write=False)
        object.__setattr__(self, "edits", edits)
        object.__setattr__(self, "stages", stages)
        object.__setattr__(self, "goals", goals)
        object.__setattr__(self, "type_index", type_index)
        object.__setattr__(self, "types", tuple(self.types))

    @classmethod
    def from_matrix(cls, matrix: Any, map: Map, robot_type: RobotType | list[RobotType],
                    settings: Settings | None = None, name: str = "scenario",
                    type_index: Any = None) -> Scenario:
        """Build from the paper's matrix: rows ``[x, y, yaw, v, x_goal, y_goal]``.

        Rows of 4 columns (no goals) are accepted for deployment and exploration.
        """
        rows = np.asarray(matrix, dtype=np.float64)
        if rows.ndim != 2 or rows.shape[1] not in (4, 6):
            raise ScenarioError(f"scenario {name!r}: the robot matrix must have 4 or 6 columns "
                                f"[x, y, yaw, v(, x_goal, y_goal)], got shape {rows.shape}")
        goals = rows[:, 4:6] if rows.shape[1] == 6 else np.full((len(rows), 2), np.nan)
        types = robot_type if isinstance(robot_type, list | tuple) else [robot_type]
        if type_index is None:
            type_index = np.zeros(len(rows), dtype=np.int64)
        return cls(map=map, types=tuple(types), type_index=type_index, stages=rows[:, :4],
                   goals=goals, settings=settings or Settings(), name=name)

    @property
    def robot_count(self) -> int:
        """Number of robots."""
        return len(self.stages)

    @property
    def has_goal(self) -> np.ndarray:
        """Boolean mask of robots that have a goal."""
        return ~np.isnan(self.goals[:, 0])

    def robot_type(self, i: int) -> RobotType:
        """The type of robot ``i``."""
        return self.types[int(self.type_index[i])]

    def with_settings(self, **changes: Any) -> Scenario:
        """A copy with some settings changed."""
        return replace(self, settings=replace(self.settings, **changes))

    def as_matrix(self) -> np.ndarray:
        """The paper's matrix form, ``(n, 6)``, NaN where a robot has no goal."""
        return np.hstack([self.stages, self.goals])
