"""World state as structure-of-arrays over robots.

Every per-robot quantity is one NumPy array indexed by robot; the ``Robot``
objects user code sees are views into these rows (``robot_view.py``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from enum import IntEnum
from functools import cached_property
from typing import Protocol

import numpy as np

from mimics.engine.dynamics import PidArrays, Plant
from mimics.engine.messages import MessageColumn
from mimics.engine.ranging.beam_fan import beam_fans, offset_units
from mimics.world.scenario import Scenario


class PendingScan(Protocol):
    """The rays of the last sensing, traced when first read (``scanner.Scanner``)."""

    def trace_all(self) -> None:
        """Trace every scanning robot's row."""

    def trace_row(self, robot: int) -> bool:
        """Trace at least ``robot``'s row; True if every row is traced now."""

    def drop(self) -> None:
        """No more reads: end any tracing still going on (the robots move next)."""


class Status(IntEnum):
    """A robot's state; every value but ACTIVE is a reason for deactivation."""

    ACTIVE = 0
    REACHED_GOAL = 1
    COLLIDED = 2
    ESCAPED = 3
    DEADLOCK = 4
    ERROR = 5
    REMOVED = 6  # taken out of the run by an edit (``mimics.engine.edits``)

    @property
    def label(self) -> str:
        """Lower-case name used in logs and tables."""
        return self.name.lower()


# ``active`` is ``status == ACTIVE``, computed as ``not status``: ACTIVE is 0, and a
# one-operand ufunc skips the scalar's conversion (1.0 against 1.7 us; an IntEnum
# member, converted the slow way, costs 8 us). The engine asks several times a step.
assert Status.ACTIVE == 0


@dataclass
class TypeArrays:
    """Robot-type parameters broadcast to one row per robot."""

    half_length: np.ndarray
    half_width: np.ndarray
    plant: Plant
    pid: PidArrays
    beam_offsets: np.ndarray  # (n, B), NaN where a robot's type has fewer beams
    beam_units: np.ndarray  # (n, B, 2): cosine and sine of each offset (the ranger rotates them)
    beam_count: np.ndarray  # (n,)
    max_range: np.ndarray
    sigma_range: np.ndarray
    sigma_position: np.ndarray
    sigma_velocity: np.ndarray
    sigma_acceleration: np.ndarray
    sigma_translation: np.ndarray
    sigma_rotation: np.ndarray

    @cached_property
    def beam_fans(self) -> np.ndarray:
        """``(n, FAN_COLUMNS)``: each row's fan, for the ranger (made when first scanned)."""
        return beam_fans(self.beam_offsets)

    @cached_property
    def noisy(self) -> frozenset[str]:
        """Names of the ``sigma_*`` fields that are above zero for some robot.

        Computed once: the sensors ask every step which noise draws to make.
        """
        return frozenset(f.name for f in fields(self)
                         if f.name.startswith("sigma_") and np.any(getattr(self, f.name) > 0))

    @classmethod
    def from_scenario(cls, scenario: Scenario) -> TypeArrays:
        """Broadcast the scenario's types to per-robot rows."""
        idx = scenario.type_index
        types = scenario.types

        def per_robot(get: object) -> np.ndarray:
            values = np.array([get(t) for t in types], dtype=np.float64)  # type: ignore[operator]
            return values[idx]

        exact = scenario.settings.noise == "off"  # the noise-free run: every sigma zero

        def sigma(get: object) -> np.ndarray:
            return np.zeros(len(idx)) if exact else per_robot(get)

        max_beams = max((t.ranger.beams for t in types), default=0)
        offsets_by_type = np.full((len(types), max_beams), np.nan)
        for k, t in enumerate(types):
            offsets_by_type[k, : t.ranger.beams] = t.ranger.beam_offsets()
        gains = lambda attr: np.array(  # noqa: E731
            [[getattr(t, attr).kp, getattr(t, attr).ki, getattr(t, attr).kd] for t in types]
        )[idx]
        return cls(
            half_length=per_robot(lambda t: t.length / 2),
            half_width=per_robot(lambda t: t.width / 2),
            plant=Plant(per_robot(lambda t: t.kv), per_robot(lambda t: t.kw),
                        per_robot(lambda t: t.tau_v), per_robot(lambda t: t.tau_w)),
            pid=PidArrays(np.ascontiguousarray(gains("speed_pid")),
                          np.ascontiguousarray(gains("heading_pid"))),
            beam_offsets=np.ascontiguousarray(offsets_by_type[idx]),
            beam_units=offset_units(offsets_by_type)[idx],
            beam_count=np.array([t.ranger.beams for t in types], dtype=np.int64)[idx],
            max_range=per_robot(lambda t: t.ranger.range),
            sigma_range=sigma(lambda t: t.ranger.sigma),
            sigma_position=sigma(lambda t: t.positioning.sigma_position),
            sigma_velocity=sigma(lambda t: t.positioning.sigma_velocity),
            sigma_acceleration=sigma(lambda t: t.positioning.sigma_acceleration),
            sigma_translation=sigma(lambda t: t.odometry.sigma_translation),
            sigma_rotation=sigma(lambda t: t.odometry.sigma_rotation),
        )


@dataclass
class WorldState:
    """All mutable per-robot state of one simulation."""

    n: int
    time: float
    step: int
    pose: np.ndarray  # (n, 3) ground truth x, y, theta
    velocity: np.ndarray  # (n, 2) ground truth v, w
    acceleration: np.ndarray  # (n, 2) dv/dt, dw/dt over the last step
    goal: np.ndarray  # (n, 2), NaN when none
    reference: np.ndarray  # (n, 2) speed and heading references last commanded
    actuation: np.ndarray  # (n, 2) u_v, u_w
    pid_integral: np.ndarray  # (n, 2)
    measured_pose: np.ndarray
    measured_velocity: np.ndarray
    measured_acceleration: np.ndarray
    odometry: np.ndarray  # (n, 3) odometer's integrated pose estimate
    scan_buffer: np.ndarray  # (n, B) ranges as last traced: read them as ``scan``
    scan_hit_buffer: np.ndarray  # (n, B) what each beam hit, as last traced: ``scan_hit``
    status: np.ndarray  # (n,) int8 Status
    deactivation_time: np.ndarray  # (n,), NaN while active
    collided_with: np.ndarray  # (n,) -2 none, -1 wall, else robot index (stall: the first)
    path_length: np.ndarray  # (n,) distance travelled
    goal_time: np.ndarray  # (n,) time the goal was reached, NaN otherwise
    user_time: np.ndarray  # (n,) seconds spent in user code at the last step
    in_deadlock: np.ndarray  # (n,) bool
    in_livelock: np.ndarray  # (n,) bool
    #: (n,) bool: the robot's move of the last step was undone, against a wall or a robot
    #: (``on_collision = "stall"``: ``mimics.engine.collision_response``); it stays active
    stalled: np.ndarray
    user_message: list[str] = field(default_factory=list)
    system_message: list[str] = field(default_factory=list)
    memory: list[dict] = field(default_factory=list)
    #: The rays of the last sensing, set by the simulation when it senses: the first
    #: read of ``scan`` or ``scan_hit`` traces them, so a step whose readers (the
    #: algorithm, the observers) read no ranger casts no ray (Stage's habit: sensors of
    #: no subscriber are not updated).
    pending_scan: PendingScan | None = None

    @classmethod
    def from_scenario(cls, scenario: Scenario, beams: int) -> WorldState:
        """The state at time zero."""
        n = scenario.robot_count
        stages = scenario.stages
        pose = np.ascontiguousarray(stages[:, :3].copy())
        velocity = np.zeros((n, 2))
        velocity[:, 0] = stages[:, 3]
        return cls(
            n=n, time=0.0, step=0, pose=pose, velocity=velocity,
            acceleration=np.zeros((n, 2)), goal=scenario.goals.copy(),
            reference=np.zeros((n, 2)), actuation=np.zeros((n, 2)),
            pid_integral=np.zeros((n, 2)), measured_pose=pose.copy(),
            measured_velocity=velocity.copy(), measured_acceleration=np.zeros((n, 2)),
            odometry=pose.copy(), scan_buffer=np.full((n, beams), np.nan),
            scan_hit_buffer=np.full((n, beams), -2, dtype=np.int64),
            status=np.zeros(n, dtype=np.int8), deactivation_time=np.full(n, np.nan),
            collided_with=np.full(n, -2, dtype=np.int64), path_length=np.zeros(n),
            goal_time=np.full(n, np.nan), user_time=np.zeros(n),
            in_deadlock=np.zeros(n, dtype=bool), in_livelock=np.zeros(n, dtype=bool),
            stalled=np.zeros(n, dtype=bool),
            user_message=MessageColumn([""] * n), system_message=MessageColumn([""] * n),
            memory=[{} for _ in range(n)],
        )

    @property
    def scan(self) -> np.ndarray:
        """``(n, B)`` ranges of the last sensing (NaN beyond a robot's beams)."""
        if self.pending_scan is not None:
            self._trace_pending()
        return self.scan_buffer

    @property
    def scan_hit(self) -> np.ndarray:
        """``(n, B)`` what each beam hit at the last sensing: -2 nothing, -1 a wall,
        else the robot's index."""
        if self.pending_scan is not None:
            self._trace_pending()
        return self.scan_hit_buffer

    def _trace_pending(self) -> None:
        pending, self.pending_scan = self.pending_scan, None
        pending.trace_all()  # type: ignore[union-attr]

    def scan_row(self, robot: int) -> None:
        """Make ``robot``'s rows of ``scan_buffer`` and ``scan_hit_buffer`` current; other
        rows may still be being traced (read them through ``scan``)."""
        pending = self.pending_scan
        if pending is not None and pending.trace_row(robot):
            self.pending_scan = None

    def drop_pending_scan(self) -> None:
        """The scan nobody read is never traced; a trace under way is ended."""
        pending, self.pending_scan = self.pending_scan, None
        if pending is not None:
            pending.drop()

    @property
    def active(self) -> np.ndarray:
        """Boolean mask of active robots."""
        return np.logical_not(self.status)

    def goal_distance(self) -> np.ndarray:
        """Distance from each robot's true position to its goal (NaN without a goal)."""
        return np.hypot(self.goal[:, 0] - self.pose[:, 0], self.goal[:, 1] - self.pose[:, 1])
