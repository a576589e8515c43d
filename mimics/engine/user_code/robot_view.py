"""What user code sees: ``robot`` (one robot) and ``team`` (all active robots).

Neither holds the simulation: they read per-step copies of the world's arrays
and ask for the rest through a link, both kept by :mod:`mimics.engine.user_code.view_hub`
(which says why, and what in-process Python cannot guarantee).

>>> # inside an algorithm
>>> # x, y, theta = robot.pose;  ranges = robot.scan.ranges;  gx, gy = robot.goal
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.sensors import COMMS_COLUMNS
from mimics.engine.user_code.view_hub import ViewHub, hub_of
from mimics.world.maps import Map
from mimics.world.robot_types import RobotType

if TYPE_CHECKING:
    from mimics.engine.user_code.world_access import SimulationParts


def _frozen(view: np.ndarray) -> np.ndarray:
    view.flags.writeable = False
    return view


def _row(views: dict[str, np.ndarray], key: str, source: np.ndarray, index: Any) -> np.ndarray:
    """A read-only view ``source[index]`` of a mirror array, made on first use and reused
    (the mirror is refreshed in place: one view shows each step's values)."""
    view = views.get(key)
    if view is None:
        view = views[key] = _frozen(source[index])
    return view


class Scan:
    """One robot's latest ranger reading."""

    __slots__ = ("_index", "_link", "_mirror", "_views")

    def __init__(self, hub: ViewHub, index: int) -> None:
        self._index = index
        self._mirror = hub.mirror
        self._link = hub.link
        self._views: dict[str, np.ndarray] = {}

    def _current(self) -> dict[str, np.ndarray]:
        mirror = self._mirror
        index = self._index
        if mirror.scan_step[index] != mirror.step:  # first read this step: trace, copy
            self._link.send(("scan_row", index))
        views = self._views
        if "ranges" not in views:
            count = mirror.beam_count[index]
            views["ranges"] = _frozen(mirror.scan[index, :count])
            views["hit_codes"] = _frozen(mirror.scan_hit[index, :count])
        return views

    @property
    def ranges(self) -> np.ndarray:
        """Distance per beam (m); ``max_range`` where nothing was hit."""
        return self._current()["ranges"]

    @property
    def angles(self) -> np.ndarray:
        """Beam angles relative to the robot's heading (rad), right to left."""
        angles = self._views.get("angles")
        if angles is None:
            angles = self._views["angles"] = self._link.send(("angles", self._index))
        return angles

    @property
    def hits(self) -> np.ndarray:
        """True where a beam hit something within range."""
        return self._current()["hit_codes"] != -2

    @property
    def max_range(self) -> float:
        """The ranger's range (m)."""
        return self._mirror.max_range[self._index]

    def points(self) -> np.ndarray:
        """Hit points in the world frame ``(hits, 2)``, from the measured pose."""
        x, y, theta = self._mirror.measured_pose[self._index]
        hit = self.hits
        angles = theta + self.angles[hit]
        r = self.ranges[hit]
        return np.column_stack([x + r * np.cos(angles), y + r * np.sin(angles)])


class _WorldView(ABC):
    """What ``robot`` and ``team`` read alike: the clock, the map, the generator and the
    communication table, asked for one robot (``robot``) or for the team (``team``)."""

    __slots__ = ()
    _link: Any
    _mirror: Any

    @abstractmethod
    def _asker(self) -> int | None:
        """Whose view this is, for the hub: a robot's index, or None for the team."""

    @property
    def time(self) -> float:
        """Simulated time (s)."""
        return self._mirror.time  # type: ignore[no-any-return]

    @property
    def dt(self) -> float:
        """The simulation step (s)."""
        return self._mirror.dt  # type: ignore[no-any-return]

    @property
    def map(self) -> Map:
        """The map: its walls as edited so far (``mimics.engine.edits``)."""
        return self._link.send(("map", self._asker()))  # type: ignore[no-any-return]

    @property
    def rng(self) -> np.random.Generator:
        """The generator for user code: the robot's own stream of the run's seed
        (``robot.rng``), or the team's (``team.rng``)."""
        return self._link.send(("rng", self._asker()))  # type: ignore[no-any-return]

    @property
    def comms(self) -> np.ndarray:
        """Rows ``[id, x, y, theta, v, w]``: of the active robots within communication
        range of this robot (``robot.comms``, its own row included), or of all active
        robots (``team.comms``)."""
        return self._link.send(("comms", self._asker()))  # type: ignore[no-any-return]


class Robot(_WorldView):
    """One robot as its algorithm sees it; every sensor is one attribute away.

    ``id``: the robot's index in the scenario (0-based), as in ``comms`` rows and
    messages. Measured (noisy) values: ``pose``, ``position``, ``velocity``,
    ``acceleration``, ``odometry``, ``scan``, ``comms``. Ground truth:
    ``true_pose``, ``true_velocity``. Also ``goal``, ``stalled``, ``time``, ``dt``, ``map``,
    ``memory`` (a dict kept between steps), ``rng`` (seeded), ``log(msg)``,
    ``send(msg, to=None)`` and ``inbox``. Arrays are read-only copies of the world's
    values at this step's sensing: nothing done to them changes the world.
    """

    __slots__ = ("_link", "_mirror", "_type", "_views", "id", "scan")

    def __init__(self, sim: SimulationParts, index: int) -> None:
        hub = hub_of(sim)  # the simulation itself is not kept
        self.id = index
        self._mirror = hub.mirror
        self._link = hub.link
        self.scan = Scan(hub, index)
        mirror = hub.mirror
        self._views: dict[str, np.ndarray] = {
            "pose": _frozen(mirror.measured_pose[index]),
            "goal": mirror.goal[index]}  # read as Python floats, never handed out
        self._type: RobotType | None = None

    def _asker(self) -> int:
        return self.id

    @property
    def pose(self) -> np.ndarray:
        """Measured ``(x, y, theta)``."""
        return self._views["pose"]

    @property
    def position(self) -> np.ndarray:
        """Measured ``(x, y)``."""
        return _row(self._views, "position", self._mirror.measured_pose, (self.id, slice(0, 2)))

    @property
    def heading(self) -> float:
        """Measured heading (rad)."""
        return float(self._views["pose"][2])

    @property
    def true_pose(self) -> np.ndarray:
        """Ground-truth ``(x, y, theta)``."""
        return _row(self._views, "true_pose", self._mirror.pose, self.id)

    @property
    def velocity(self) -> np.ndarray:
        """Measured ``(v, w)``: speed (m/s) and turn rate (rad/s)."""
        return _row(self._views, "velocity", self._mirror.measured_velocity, self.id)

    @property
    def true_velocity(self) -> np.ndarray:
        """Ground-truth ``(v, w)``."""
        return _row(self._views, "true_velocity", self._mirror.velocity, self.id)

    @property
    def acceleration(self) -> np.ndarray:
        """Measured ``(dv/dt, dw/dt)``."""
        return _row(self._views, "acceleration", self._mirror.measured_acceleration, self.id)

    @property
    def odometry(self) -> np.ndarray:
        """The odometer's integrated ``(x, y, theta)`` estimate (drifts with motion)."""
        return _row(self._views, "odometry", self._mirror.odometry, self.id)

    @property
    def stalled(self) -> bool:
        """True when its last move was undone against a wall or a robot (Stage's stall, under
        the setting ``on_collision = "stall"``); it stays active and can drive away."""
        return self._link.send(("stalled", self.id))  # type: ignore[no-any-return]

    @property
    def goal(self) -> tuple[float, float] | None:
        """``(x, y)`` of the goal, or None for robots without one."""
        gx, gy = self._views["goal"].tolist()  # Python floats in one call
        return None if math.isnan(gx) else (gx, gy)

    @property
    def type(self) -> RobotType:
        """This robot's type (dimensions, dynamics, sensors)."""
        if self._type is None:  # looked up once: a scenario (frozen) never changes it
            self._type = self._link.send(("type", self.id))
        return self._type

    @property
    def memory(self) -> dict[str, Any]:
        """A dict that persists between this robot's steps."""
        return self._link.send(("memory", self.id))  # type: ignore[no-any-return]

    comms_columns = COMMS_COLUMNS

    @property
    def inbox(self) -> list[tuple[int, Any]]:
        """Messages ``(sender_id, message)`` delivered to this robot this step."""
        return self._link.send(("inbox", self.id))  # type: ignore[no-any-return]

    def send(self, message: Any, to: int | None = None) -> None:
        """Send a message to robot ``to`` (or to all within range); it arrives next step."""
        self._link.send(("send", self.id, message, to))

    def log(self, message: str) -> None:
        """Add a message to this step's ``user_msg`` column of the log."""
        self._link.send(("log", self.id, message))

    def __repr__(self) -> str:
        x, y, theta = self._mirror.pose[self.id]
        return f"Robot(id={self.id}, x={x:.3f}, y={y:.3f}, theta={theta:.3f})"


class TeamScan:
    """Latest scans of the team's robots: ``ranges (k, B)`` and ``angles (k, B)``."""

    __slots__ = ("_link", "_mirror", "_read", "_rows")

    def __init__(self, hub: ViewHub, rows: np.ndarray) -> None:
        self._mirror = hub.mirror
        self._link = hub.link
        self._rows = rows
        self._read: dict[str, np.ndarray] | None = None

    def _traced(self) -> dict[str, np.ndarray]:
        if self._read is None:
            self._read = self._link.send(("team_scan", self._rows))
        return self._read

    @property
    def ranges(self) -> np.ndarray:
        """Distances ``(k, B)``; NaN in slots beyond a robot's beam count."""
        return self._traced()["ranges"]

    @property
    def angles(self) -> np.ndarray:
        """Beam angles relative to each heading ``(k, B)``."""
        return self._link.send(("team_angles", self._rows))  # type: ignore[no-any-return]

    @property
    def hits(self) -> np.ndarray:
        """True where a beam hit something."""
        return self._traced()["hits"]

    @property
    def max_range(self) -> np.ndarray:
        """Each robot's ranger range ``(k,)``."""
        return np.asarray(self._mirror.max_range)[self._rows]


class Team(_WorldView):
    """All robots an algorithm drives in one call, as arrays (first axis = robot).

    ``ids`` are the robots' indices; ``pose``, ``velocity``, ``goal`` (NaN rows
    for no goal), ``scan.ranges`` etc. are arrays of matching rows, copies of the
    world's: nothing done to them changes the world.
    """

    __slots__ = ("_link", "_mirror", "ids", "scan")

    def __init__(self, sim: SimulationParts, ids: np.ndarray) -> None:
        hub = hub_of(sim)  # the simulation itself is not kept
        hub.refresh()  # a team view is made for each call: it shows this step's values
        self._mirror = hub.mirror
        self._link = hub.link
        self.ids = np.array(ids, copy=True)
        self.scan = TeamScan(hub, self.ids)

    def __len__(self) -> int:
        return len(self.ids)

    def _asker(self) -> None:
        return None

    @property
    def pose(self) -> np.ndarray:
        """Measured poses ``(k, 3)``."""
        return self._mirror.measured_pose[self.ids]

    @property
    def true_pose(self) -> np.ndarray:
        """Ground-truth poses ``(k, 3)``."""
        return self._mirror.pose[self.ids]

    @property
    def velocity(self) -> np.ndarray:
        """Measured ``(v, w)`` rows ``(k, 2)``."""
        return self._mirror.measured_velocity[self.ids]

    def _types(self) -> dict[str, np.ndarray]:
        return self._link.send(("team_types", self.ids))  # type: ignore[no-any-return]

    @property
    def max_speed(self) -> np.ndarray:
        """Each robot's top speed ``(k,)`` (m/s, its type's ``kv``)."""
        return self._types()["kv"]

    @property
    def length(self) -> np.ndarray:
        """Each robot's length ``(k,)`` (m, along its heading)."""
        return 2.0 * self._types()["half_length"]

    @property
    def width(self) -> np.ndarray:
        """Each robot's width ``(k,)`` (m)."""
        return 2.0 * self._types()["half_width"]

    @property
    def odometry(self) -> np.ndarray:
        """Odometer estimates ``(k, 3)``."""
        return self._mirror.odometry[self.ids]

    @property
    def stalled(self) -> np.ndarray:
        """``(k,)`` bool: each robot's last move undone against a wall or a robot
        (``on_collision = "stall"``, see ``robot.stalled``)."""
        return self._link.send(("stalled", self.ids))  # type: ignore[no-any-return]

    @property
    def goal(self) -> np.ndarray:
        """Goals ``(k, 2)``, NaN rows for robots without one."""
        return self._mirror.goal[self.ids]

    @property
    def memory(self) -> dict[str, Any]:
        """A dict shared by the team, kept between steps."""
        return self._link.send(("team_memory", None))  # type: ignore[no-any-return]

    def log(self, robot_id: int, message: str) -> None:
        """Add a message to robot ``robot_id``'s ``user_msg`` column this step."""
        self._link.send(("log", int(robot_id), message))
