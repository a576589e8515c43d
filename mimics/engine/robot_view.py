"""What user code sees: ``robot`` (one robot) and ``team`` (all active robots).

Both are thin views over the world's arrays: reading ``robot.pose`` gives a
read-only view of that robot's row, never a copy of the world.

>>> # inside an algorithm
>>> # x, y, theta = robot.pose;  ranges = robot.scan.ranges;  gx, gy = robot.goal
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.sensors import COMMS_COLUMNS, within_range
from mimics.world.maps import Map
from mimics.world.robot_types import RobotType

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation


def _frozen(view: np.ndarray) -> np.ndarray:
    view.flags.writeable = False
    return view


_Views = dict[str, tuple[np.ndarray, np.ndarray]]


def _row_view(views: _Views, key: str, source: np.ndarray, index: Any) -> np.ndarray:
    """A read-only view ``source[index]``, made on first use and then reused.

    The engine updates its arrays in place, so one view shows the current
    values at every step: user code reading a sensor pays a dict look-up, not
    a new view. The view is remade if ``source`` is ever a different array.
    """
    hit = views.get(key)
    if hit is None or hit[0] is not source:
        hit = views[key] = (source, _frozen(source[index]))
    return hit[1]


class Scan:
    """One robot's latest ranger reading."""

    __slots__ = ("_index", "_sim", "_views")

    def __init__(self, sim: Simulation, index: int) -> None:
        self._sim = sim
        self._index = index
        self._views: _Views = {}

    def _beams(self) -> tuple[int, slice]:
        return self._index, slice(0, int(self._sim.types.beam_count[self._index]))

    @property
    def ranges(self) -> np.ndarray:
        """Distance per beam (m); ``max_range`` where nothing was hit."""
        state = self._sim.state
        if state.pending_scan is not None:  # this row only: the others may be traced meanwhile
            state.scan_row(self._index)
        hit = self._views.get("ranges")
        source = state.scan_buffer
        if hit is not None and hit[0] is source:  # the common case, inlined
            return hit[1]
        return _row_view(self._views, "ranges", source, self._beams())

    @property
    def angles(self) -> np.ndarray:
        """Beam angles relative to the robot's heading (rad), right to left."""
        hit = self._views.get("angles")
        source = self._sim.types.beam_offsets
        if hit is not None and hit[0] is source:
            return hit[1]
        return _row_view(self._views, "angles", source, self._beams())

    @property
    def hits(self) -> np.ndarray:
        """True where a beam hit something within range."""
        state = self._sim.state
        if state.pending_scan is not None:
            state.scan_row(self._index)
        count = self._sim.types.beam_count[self._index]
        return state.scan_hit_buffer[self._index, :count] != -2

    @property
    def max_range(self) -> float:
        """The ranger's range (m)."""
        return float(self._sim.types.max_range[self._index])

    def points(self) -> np.ndarray:
        """Hit points in the world frame ``(hits, 2)``, from the measured pose."""
        x, y, theta = self._sim.state.measured_pose[self._index]
        hit = self.hits
        angles = theta + self.angles[hit]
        r = self.ranges[hit]
        return np.column_stack([x + r * np.cos(angles), y + r * np.sin(angles)])


class Robot:
    """One robot as its algorithm sees it; every sensor is one attribute away.

    ``id``: the robot's index in the scenario (0-based), as in ``comms`` rows and
    messages. Measured (noisy) values: ``pose``, ``position``, ``velocity``,
    ``acceleration``, ``odometry``, ``scan``, ``comms``. Ground truth:
    ``true_pose``, ``true_velocity``. Also ``goal``, ``time``, ``dt``, ``map``,
    ``memory`` (a dict kept between steps), ``rng`` (seeded), ``log(msg)``,
    ``send(msg, to=None)`` and ``inbox``.
    """

    __slots__ = ("_sim", "_type", "_views", "id", "scan")

    def __init__(self, sim: Simulation, index: int) -> None:
        self._sim = sim
        self.id = index
        self.scan = Scan(sim, index)
        self._views: _Views = {}
        self._type: RobotType | None = None

    @property
    def pose(self) -> np.ndarray:
        """Measured ``(x, y, theta)``."""
        hit = self._views.get("pose")
        source = self._sim.state.measured_pose
        if hit is not None and hit[0] is source:  # the common case, inlined (as Scan.ranges)
            return hit[1]
        return _row_view(self._views, "pose", source, self.id)

    @property
    def position(self) -> np.ndarray:
        """Measured ``(x, y)``."""
        return _row_view(self._views, "position", self._sim.state.measured_pose,
                         (self.id, slice(0, 2)))

    @property
    def heading(self) -> float:
        """Measured heading (rad)."""
        return float(self._sim.state.measured_pose[self.id, 2])

    @property
    def true_pose(self) -> np.ndarray:
        """Ground-truth ``(x, y, theta)``."""
        return _row_view(self._views, "true_pose", self._sim.state.pose, self.id)

    @property
    def velocity(self) -> np.ndarray:
        """Measured ``(v, w)``: speed (m/s) and turn rate (rad/s)."""
        return _row_view(self._views, "velocity", self._sim.state.measured_velocity, self.id)

    @property
    def true_velocity(self) -> np.ndarray:
        """Ground-truth ``(v, w)``."""
        return _row_view(self._views, "true_velocity", self._sim.state.velocity, self.id)

    @property
    def acceleration(self) -> np.ndarray:
        """Measured ``(dv/dt, dw/dt)``."""
        return _row_view(self._views, "acceleration", self._sim.state.measured_acceleration,
                         self.id)

    @property
    def odometry(self) -> np.ndarray:
        """The odometer's integrated ``(x, y, theta)`` estimate (drifts with motion)."""
        return _row_view(self._views, "odometry", self._sim.state.odometry, self.id)

    @property
    def goal(self) -> tuple[float, float] | None:
        """``(x, y)`` of the goal, or None for robots without one."""
        hit = self._views.get("goal")  # kept as views, the common case inlined
        source = self._sim.state.goal
        row = (hit[1] if hit is not None and hit[0] is source
               else _row_view(self._views, "goal", source, self.id))
        gx, gy = row.tolist()  # Python floats in one call
        return None if math.isnan(gx) else (gx, gy)

    @property
    def time(self) -> float:
        """Simulated time (s)."""
        return self._sim.state.time

    @property
    def dt(self) -> float:
        """The simulation step (s)."""
        return self._sim.scenario.settings.dt

    @property
    def type(self) -> RobotType:
        """This robot's type (dimensions, dynamics, sensors)."""
        if self._type is None:  # looked up once: a scenario (frozen) never changes it
            self._type = self._sim.scenario.robot_type(self.id)
        return self._type

    @property
    def map(self) -> Map:
        """The map: its walls as edited so far (``mimics.engine.edits``)."""
        return self._sim.world_map

    @property
    def memory(self) -> dict[str, Any]:
        """A dict that persists between this robot's steps."""
        return self._sim.state.memory[self.id]

    @property
    def rng(self) -> np.random.Generator:
        """This robot's generator for user code: its own stream of the run's seed."""
        return self._sim.user_rng(self.id)

    @property
    def comms(self) -> np.ndarray:
        """Rows ``[id, x, y, theta, v, w]`` of active robots within communication range."""
        x, y = self._sim.state.measured_pose[self.id, :2]
        return within_range(self._sim.comms_table(), x, y, self._sim.scenario.settings.comm_range)

    comms_columns = COMMS_COLUMNS

    @property
    def inbox(self) -> list[tuple[int, Any]]:
        """Messages ``(sender_id, message)`` delivered to this robot this step."""
        return self._sim.messages.inbox(self.id)

    def send(self, message: Any, to: int | None = None) -> None:
        """Send a message to robot ``to`` (or to all within range); it arrives next step."""
        self._sim.messages.send(self.id, message, to)

    def log(self, message: str) -> None:
        """Add a message to this step's ``user_msg`` column of the log."""
        current = self._sim.state.user_message[self.id]
        text = f"{current} | {message}" if current else str(message)
        self._sim.state.user_message[self.id] = text

    def __repr__(self) -> str:
        x, y, theta = self._sim.state.pose[self.id]
        return f"Robot(id={self.id}, x={x:.3f}, y={y:.3f}, theta={theta:.3f})"


class TeamScan:
    """Latest scans of the team's robots: ``ranges (k, B)`` and ``angles (k, B)``."""

    __slots__ = ("_rows", "_sim")

    def __init__(self, sim: Simulation, rows: np.ndarray) -> None:
        self._sim = sim
        self._rows = rows

    @property
    def ranges(self) -> np.ndarray:
        """Distances ``(k, B)``; NaN in slots beyond a robot's beam count."""
        return self._sim.state.scan[self._rows]

    @property
    def angles(self) -> np.ndarray:
        """Beam angles relative to each heading ``(k, B)``."""
        return self._sim.types.beam_offsets[self._rows]

    @property
    def hits(self) -> np.ndarray:
        """True where a beam hit something."""
        return self._sim.state.scan_hit[self._rows] != -2

    @property
    def max_range(self) -> np.ndarray:
        """Each robot's ranger range ``(k,)``."""
        return self._sim.types.max_range[self._rows]


class Team:
    """All robots an algorithm drives in one call, as arrays (first axis = robot).

    ``ids`` are the robots' indices; ``pose``, ``velocity``, ``goal`` (NaN rows
    for no goal), ``scan.ranges`` etc. are arrays of matching rows.
    """

    __slots__ = ("_sim", "ids", "scan")

    def __init__(self, sim: Simulation, ids: np.ndarray) -> None:
        self._sim = sim
        self.ids = ids
        self.scan = TeamScan(sim, ids)

    def __len__(self) -> int:
        return len(self.ids)

    @property
    def pose(self) -> np.ndarray:
        """Measured poses ``(k, 3)``."""
        return self._sim.state.measured_pose[self.ids]

    @property
    def true_pose(self) -> np.ndarray:
        """Ground-truth poses ``(k, 3)``."""
        return self._sim.state.pose[self.ids]

    @property
    def velocity(self) -> np.ndarray:
        """Measured ``(v, w)`` rows ``(k, 2)``."""
        return self._sim.state.measured_velocity[self.ids]

    @property
    def max_speed(self) -> np.ndarray:
        """Each robot's top speed ``(k,)`` (m/s, its type's ``kv``)."""
        return self._sim.types.plant.kv[self.ids]

    @property
    def length(self) -> np.ndarray:
        """Each robot's length ``(k,)`` (m, along its heading)."""
        return 2.0 * self._sim.types.half_length[self.ids]

    @property
    def width(self) -> np.ndarray:
        """Each robot's width ``(k,)`` (m)."""
        return 2.0 * self._sim.types.half_width[self.ids]

    @property
    def odometry(self) -> np.ndarray:
        """Odometer estimates ``(k, 3)``."""
        return self._sim.state.odometry[self.ids]

    @property
    def goal(self) -> np.ndarray:
        """Goals ``(k, 2)``, NaN rows for robots without one."""
        return self._sim.state.goal[self.ids]

    @property
    def time(self) -> float:
        """Simulated time (s)."""
        return self._sim.state.time

    @property
    def dt(self) -> float:
        """The simulation step (s)."""
        return self._sim.scenario.settings.dt

    @property
    def map(self) -> Map:
        """The map: its walls as edited so far (``mimics.engine.edits``)."""
        return self._sim.world_map

    @property
    def memory(self) -> dict[str, Any]:
        """A dict shared by the team, kept between steps."""
        return self._sim.team_memory

    @property
    def rng(self) -> np.random.Generator:
        """The team's generator for user code: its own stream of the run's seed."""
        return self._sim.user_rng()

    @property
    def comms(self) -> np.ndarray:
        """Rows ``[id, x, y, theta, v, w]`` of all active robots."""
        return self._sim.comms_table()

    def log(self, robot_id: int, message: str) -> None:
        """Add a message to robot ``robot_id``'s ``user_msg`` column this step."""
        Robot(self._sim, int(robot_id)).log(message)
