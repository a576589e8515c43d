"""Robot types: the physical and sensing description of a kind of robot.

A :class:`RobotType` is plain, immutable data. The built-in library holds the
paper's robots; users make their own with :func:`dataclasses.replace` or load
them from TOML with :func:`load_robot_types`.

>>> from mimics.world.robot_types import PIONEER_3AT
>>> PIONEER_3AT.length, PIONEER_3AT.ranger.beams
(0.7, 270)
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

from mimics.world.errors import ScenarioError, read_input_text
from mimics.world.limits import MAX_BEAMS


@dataclass(frozen=True)
class PidGains:
    """Gains of one PID loop (output saturated to [-1, 1], with anti-windup)."""

    kp: float
    ki: float = 0.0
    kd: float = 0.0


@dataclass(frozen=True)
class RangerSpec:
    """A planar range finder: ``beams`` rays spread evenly over ``fov`` radians."""

    name: str = "none"
    fov: float = 0.0
    beams: int = 0
    range: float = 0.0
    sigma: float = 0.0

    def beam_offsets(self) -> tuple[float, ...]:
        """Beam angles relative to the heading, from right (-fov/2) to left (+fov/2)."""
        if self.beams <= 0:
            return ()
        if self.beams == 1:
            return (0.0,)
        if math.isclose(self.fov, 2 * math.pi):
            step = self.fov / self.beams  # a full circle: do not repeat the first beam
        else:
            step = self.fov / (self.beams - 1)
        return tuple(-self.fov / 2 + i * step for i in range(self.beams))


@dataclass(frozen=True)
class PositioningNoise:
    """Standard deviations of the positioning sensor (m, m/s, m/s^2)."""

    sigma_position: float = 0.0
    sigma_velocity: float = 0.0
    sigma_acceleration: float = 0.0


@dataclass(frozen=True)
class OdometryNoise:
    """Odometry noise, applied only while moving, so that it accumulates with motion.

    Each step's measured increment is the true one plus Gaussian noise whose
    standard deviation is ``sigma_translation`` per metre travelled and
    ``sigma_rotation`` per radian turned (so the result does not depend on dt).
    """

    sigma_translation: float = 0.0  # m of noise per m travelled
    sigma_rotation: float = 0.0  # rad of noise per rad turned


@dataclass(frozen=True)
class RobotType:
    """A kind of rectangular differential-drive robot (paper section 3.1).

    ``length`` is along the heading, ``width`` across it. Dynamics follow
    ``v' = (-v + kv*u_v)/tau_v`` and ``w' = (-w + kw*u_w)/tau_w``.
    """

    name: str
    width: float
    length: float
    kv: float
    kw: float
    tau_v: float
    tau_w: float
    ranger: RangerSpec = field(default_factory=RangerSpec)
    speed_pid: PidGains = field(default_factory=lambda: PidGains(kp=2.0, ki=2.0))
    heading_pid: PidGains = field(default_factory=lambda: PidGains(kp=2.0, ki=0.0, kd=0.1))
    positioning: PositioningNoise = field(default_factory=PositioningNoise)
    odometry: OdometryNoise = field(default_factory=OdometryNoise)

    def __post_init__(self) -> None:
        for name in ("width", "length", "tau_v", "tau_w"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise ScenarioError(f"robot type {self.name!r}: {name} must be a positive number, "
                                    f"got {value!r}")
        for name in ("kv", "kw"):
            value = getattr(self, name)
            if not (isinstance(value, int | float) and math.isfinite(value) and value > 0):
                raise ScenarioError(f"robot type {self.name!r}: {name} must be a positive number, "
                                    f"got {value!r}")
        ranger = self.ranger
        if (isinstance(ranger.beams, bool) or not isinstance(ranger.beams, int)
                or not 0 <= ranger.beams <= MAX_BEAMS):
            raise ScenarioError(f"robot type {self.name!r}: ranger beams: expected a whole "
                                f"number from 0 to {MAX_BEAMS}, got {ranger.beams!r}")
        groups = {"ranger": (ranger, ("fov", "range", "sigma")),
                  "positioning": (self.positioning, ("sigma_position", "sigma_velocity",
                                                     "sigma_acceleration")),
                  "odometry": (self.odometry, ("sigma_translation", "sigma_rotation"))}
        for group, (part, names) in groups.items():
            for name in names:
                value = getattr(part, name)
                if not _finite(value) or value < 0:
                    raise ScenarioError(f"robot type {self.name!r}: {group}.{name}: expected a "
                                        f"finite number >= 0, got {value!r}")
        for group in ("speed_pid", "heading_pid"):
            for name in ("kp", "ki", "kd"):
                value = getattr(getattr(self, group), name)
                if not _finite(value):
                    raise ScenarioError(f"robot type {self.name!r}: {group}.{name}: expected a "
                                        f"finite number, got {value!r}")
        if ranger.fov > 2 * math.pi + 1e-9:
            raise ScenarioError(f"robot type {self.name!r}: ranger fov is in radians and at most "
                                f"2*pi, got {ranger.fov}")

    @property
    def max_speed(self) -> float:
        """The steady-state speed at full actuation (m/s)."""
        return self.kv

    @property
    def max_turn_rate(self) -> float:
        """The steady-state turn rate at full actuation (rad/s)."""
        return self.kw

    def to_dict(self) -> dict[str, Any]:
        """A nested dict, the TOML form of this type."""
        return asdict(self)


def _finite(value: object) -> bool:
    return (isinstance(value, int | float) and not isinstance(value, bool)
            and math.isfinite(value))


def _ranger(name: str, fov_degrees: float, beams: int, range_m: float) -> RangerSpec:
    return RangerSpec(name=name, fov=math.radians(fov_degrees), beams=beams, range=range_m)


PIONEER_3AT = RobotType(
    name="Pioneer3AT", width=0.5, length=0.7, kv=1.0, kw=1.0, tau_v=0.5, tau_w=0.2,
    ranger=_ranger("Hokuyo UTM-30LX (simplified)", 270, 270, 30.0),
)
PIONEER_2DX = RobotType(
    name="Pioneer2DX", width=0.27, length=0.325, kv=0.3, kw=1.0, tau_v=0.05, tau_w=0.2,
    ranger=_ranger("SICK LMS200", 180, 180, 8.0),
)
SWARMBOT = RobotType(
    name="Swarmbot", width=0.1, length=0.1, kv=0.3, kw=1.0, tau_v=0.05, tau_w=0.2,
    ranger=_ranger("SICK LMS200 (2 m)", 180, 180, 2.0),
)

BUILTIN_ROBOT_TYPES: dict[str, RobotType] = {
    t.name: t for t in (PIONEER_3AT, PIONEER_2DX, SWARMBOT)
}


def robot_type_from_dict(data: dict[str, Any], where: str = "robot type") -> RobotType:
    """Build a :class:`RobotType` from its nested-dict form, rejecting unknown keys.

    A ``base`` key names a built-in type to start from (a prototype, as in
    Stage's ``define``); the other keys override it.
    """
    data = dict(data)
    base_name = data.pop("base", None)
    if base_name is not None:
        if base_name not in BUILTIN_ROBOT_TYPES:
            raise ScenarioError(f"{where}: base {base_name!r} is not a built-in robot type "
                                f"(expected one of {', '.join(BUILTIN_ROBOT_TYPES)})")
        merged = BUILTIN_ROBOT_TYPES[base_name].to_dict()
        for key, value in data.items():
            if isinstance(value, dict) and isinstance(merged.get(key), dict):
                merged[key] = {**merged[key], **value}
            else:
                merged[key] = value
        data = merged
    nested = {"ranger": RangerSpec, "speed_pid": PidGains, "heading_pid": PidGains,
              "positioning": PositioningNoise, "odometry": OdometryNoise}
    known = {f.name for f in fields(RobotType)}
    unknown = sorted(set(data) - known)
    if unknown:
        raise ScenarioError(f"{where}: unknown key {unknown[0]!r} (expected one of "
                            f"{', '.join(sorted(known | {'base'}))})")
    missing = sorted(f.name for f in fields(RobotType)
                     if f.name not in data and f.name not in nested)
    if missing:
        raise ScenarioError(f"{where}: missing key {missing[0]!r}")
    kwargs: dict[str, Any] = {}
    for key, value in data.items():
        if key in nested:
            cls = nested[key]
            if not isinstance(value, dict):
                raise ScenarioError(f"{where}.{key}: expected a table, got {value!r}")
            sub_known = {f.name for f in fields(cls)}
            bad = sorted(set(value) - sub_known)
            if bad:
                raise ScenarioError(f"{where}.{key}: unknown key {bad[0]!r} (expected one of "
                                    f"{', '.join(sorted(sub_known))})")
            kwargs[key] = cls(**value)
        else:
            kwargs[key] = value
    if "fov_degrees" in data.get("ranger", {}):
        raise ScenarioError(f"{where}.ranger: use fov in radians")
    for key in ("width", "length", "kv", "kw", "tau_v", "tau_w"):
        if not isinstance(kwargs[key], int | float) or isinstance(kwargs[key], bool):
            raise ScenarioError(f"{where}.{key}: expected a number, got {kwargs[key]!r}")
    return RobotType(**kwargs)


def load_robot_types(path: str | Path) -> dict[str, RobotType]:
    """Read robot types from a TOML file with one ``[types.NAME]`` table per type."""
    path = Path(path)
    try:
        data = tomllib.loads(read_input_text(path, "robot types", ScenarioError))
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{path}: not valid TOML ({exc})") from exc
    tables = data.get("types")
    if not isinstance(tables, dict) or not tables:
        raise ScenarioError(f"{path}: expected one or more [types.NAME] tables")
    result = {}
    for name, table in tables.items():
        result[name] = robot_type_from_dict({"name": name, **table}, f"{path}: types.{name}")
    return result

