"""Robot types: the physical and sensing description of a kind of robot.

A :class:`RobotType` is plain, immutable data. The built-in library holds the
paper's robots (Pioneer 3-AT, Pioneer 2-DX, the Hospital's swarm robot) and
robots people teach and research with (TurtleBot3 Burger, e-puck,
Kobuki/TurtleBot2, a generic point robot); users make their own with
:func:`dataclasses.replace` or load them from TOML with
:func:`load_robot_types`.

Every type's speed and heading gains default to the rule of
:mod:`mimics.world.tuning` for its own plant (``kv, tau_v, kw, tau_w``)
unless the type gives its own: the speed PI's zero cancels the sampled plant
pole and its gain puts the closed-loop pole at ``exp(-dt/0.25 s)``; the
heading PD puts both closed-loop poles at ``exp(-dt/0.12 s)``; both designed
at ``dt = 0.1`` s. A speed step or a stop that does not saturate the actuator
then settles within 2% in 1.0 s without overshoot, and a 90 degree turn
within 2 degrees in at most 1.9 s (the types with ``kw = 1`` rad/s, which
need 1.6 s at full turn rate), without overshoot (tested in
``tests/engine/test_closed_loop.py``).

>>> from mimics.world.robot_types import PIONEER_3AT
>>> PIONEER_3AT.length, PIONEER_3AT.ranger.beams
(0.7, 270)
>>> round(PIONEER_3AT.speed_pid.kp, 3), round(PIONEER_3AT.speed_pid.ki, 3)
(1.489, 3.297)
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import asdict, dataclass, field, fields
from itertools import pairwise
from pathlib import Path
from typing import Any

from mimics.world.errors import ScenarioError, read_input_text
from mimics.world.limits import MAX_BEAMS
from mimics.world.noise_sources import NOISE_SOURCES  # noqa: F401 (re-exported)
from mimics.world.tuning import heading_gains, speed_gains


@dataclass(frozen=True)
class PidGains:
    """Gains of one PID loop (output saturated to [-1, 1], with anti-windup)."""

    kp: float
    ki: float = 0.0
    kd: float = 0.0


@dataclass(frozen=True)
class RangerSpec:
    """A planar range finder: ``beams`` rays spread evenly over ``fov`` radians.

    ``angles``, when given, places the beams explicitly instead (radians from
    the heading, counterclockwise, in increasing order, one per beam): for
    sensors that are not an even fan, such as the e-puck's eight infrared
    proximity sensors. ``fov`` is then informational (their span).
    """

    name: str = "none"
    fov: float = 0.0
    beams: int = 0
    range: float = 0.0
    sigma: float = 0.0
    angles: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        # a TOML file gives a list; the type stays hashable and immutable
        object.__setattr__(self, "angles", tuple(float(a) for a in self.angles))

    def beam_offsets(self) -> tuple[float, ...]:
        """Beam angles relative to the heading, from right (-fov/2) to left (+fov/2)."""
        if self.angles:
            return self.angles
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
    ``v' = (-v + kv*u_v)/tau_v`` and ``w' = (-w + kw*u_w)/tau_w``. Gains left
    out (None) are set by the tuning rule of ``mimics.world.tuning`` for
    this plant.
    """

    name: str
    width: float
    length: float
    kv: float
    kw: float
    tau_v: float
    tau_w: float
    ranger: RangerSpec = field(default_factory=RangerSpec)
    speed_pid: PidGains | None = None
    heading_pid: PidGains | None = None
    positioning: PositioningNoise = field(default_factory=PositioningNoise)
    odometry: OdometryNoise = field(default_factory=OdometryNoise)

    def __post_init__(self) -> None:
        for name in ("width", "length", "tau_v", "tau_w", "kv", "kw"):
            value = getattr(self, name)
            if not (_finite(value) and value > 0):
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
        if self.speed_pid is None:
            object.__setattr__(self, "speed_pid", PidGains(*speed_gains(self.kv, self.tau_v)))
        if self.heading_pid is None:
            object.__setattr__(self, "heading_pid",
                               PidGains(*heading_gains(self.kw, self.tau_w)))
        for group in ("speed_pid", "heading_pid"):
            for name in ("kp", "ki", "kd"):
                value = getattr(getattr(self, group), name)
                if not _finite(value):
                    raise ScenarioError(f"robot type {self.name!r}: {group}.{name}: expected a "
                                        f"finite number, got {value!r}")
        if ranger.fov > 2 * math.pi + 1e-9:
            raise ScenarioError(f"robot type {self.name!r}: ranger fov is in radians and at most "
                                f"2*pi, got {ranger.fov}")
        angles = ranger.angles
        if angles and (len(angles) != ranger.beams or any(not -math.pi <= a <= math.pi
                                                           for a in angles)
                       or any(b <= a for a, b in pairwise(angles))):
            raise ScenarioError(f"robot type {self.name!r}: ranger angles must be {ranger.beams} "
                                "increasing angles in [-pi, pi] radians (one per beam), got "
                                f"{list(angles)}")

    @property
    def max_speed(self) -> float:
        """The steady-state speed at full actuation (m/s)."""
        return self.kv

    @property
    def max_turn_rate(self) -> float:
        """The steady-state turn rate at full actuation (rad/s)."""
        return self.kw

    def to_dict(self) -> dict[str, Any]:
        """A nested dict, the TOML form of this type (``ranger.angles`` only when set)."""
        data = asdict(self)
        if not self.ranger.angles:
            del data["ranger"]["angles"]
        else:
            data["ranger"]["angles"] = list(self.ranger.angles)
        return data


def _finite(value: object) -> bool:
    return (isinstance(value, int | float) and not isinstance(value, bool)
            and math.isfinite(value))


# Stage's position model's default odom_error [0.03 0.03 0.00 0.05] (x, y, z, heading
# proportions): the Stage robots' odometry noise, as a Gaussian per metre and per radian
STAGE_ODOMETRY = OdometryNoise(sigma_translation=0.03, sigma_rotation=0.05)

PIONEER_3AT = RobotType(
    name="Pioneer3AT", width=0.5, length=0.7, kv=1.0, kw=1.0, tau_v=0.5, tau_w=0.2,
    ranger=RangerSpec(name="Hokuyo UTM-30LX (simplified)", fov=math.radians(270), beams=270,
                      range=30.0, sigma=0.03),
    odometry=STAGE_ODOMETRY,
)
"""The paper's Pioneer 3-AT (section 5.1). Tuned gains: speed kp 1.489, ki 3.297;
heading kp 8.125, kd 1.434."""

PIONEER_2DX = RobotType(
    name="Pioneer2DX", width=0.27, length=0.325, kv=0.3, kw=1.0, tau_v=0.05, tau_w=0.2,
    ranger=RangerSpec(name="SICK LMS200", fov=math.pi, beams=180, range=8.0, sigma=0.015),
    odometry=STAGE_ODOMETRY,
)
"""The paper's Pioneer 2-DX (the Cave). Tuned gains: speed kp 0.172, ki 10.99;
heading kp 8.125, kd 1.434."""

SWARMBOT = RobotType(
    name="Swarmbot", width=0.1, length=0.1, kv=0.3, kw=1.0, tau_v=0.05, tau_w=0.2,
    ranger=RangerSpec(name="SICK LMS200 (2 m)", fov=math.pi, beams=180, range=2.0, sigma=0.015),
    odometry=STAGE_ODOMETRY,
)
"""The Hospital's 0.1 m robot: Pioneer 2-DX dynamics, a 2 m LMS200. Gains as the 2-DX."""

TURTLEBOT3_BURGER = RobotType(
    name="TurtleBot3Burger", width=0.178, length=0.138, kv=0.22, kw=2.84,
    tau_v=0.22 / 2.5, tau_w=2.84 / 3.2,
    ranger=RangerSpec(name="LDS-01", fov=2 * math.pi, beams=360, range=3.5, sigma=0.015),
)
"""ROBOTIS TurtleBot3 Burger.

Sources: ROBOTIS e-Manual, TurtleBot3 specifications (size L x W x H
138 x 178 x 192 mm; maximum translational velocity 0.22 m/s, maximum
rotational velocity 2.84 rad/s; LDS-01 360 degree laser distance sensor,
1 degree resolution, 0.12-3.5 m, accuracy +-15 mm below 0.5 m, taken here as
the noise sigma). ROBOTIS publishes no motor time constant: ``tau`` is the
maximum velocity over the acceleration limits of ROBOTIS' own navigation
set-up (``turtlebot3_navigation/param/dwa_local_planner_params_burger.yaml``:
``acc_lim_x`` 2.5 m/s^2, ``acc_lim_theta`` 3.2 rad/s^2), so that the lag's
initial acceleration at full actuation is that limit: ``tau_v`` = 0.088 s,
``tau_w`` = 0.8875 s. The LDS-01's 0.12 m minimum range is not modelled (the
ranger has none). Tuned gains: speed kp 0.708, ki 14.99; heading kp 10.56,
kd 2.846.
"""

EPUCK = RobotType(
    name="e-puck", width=0.07, length=0.07, kv=0.1288, kw=2 * 0.1288 / 0.053,
    tau_v=0.05, tau_w=0.05,
    ranger=RangerSpec(name="8 IR proximity sensors (TCRT1000)", fov=math.radians(284), beams=8,
                      range=0.1, sigma=0.003,
                      angles=tuple(math.radians(a) for a in (-142, -90, -45, -18,
                                                             18, 45, 90, 142))),
)
"""EPFL / GCtronic e-puck (version 1), the swarm robot.

Sources: GCtronic e-puck documentation (70 mm diameter, modelled as a 70 mm
square; wheel diameter 41 mm, 53 mm between the wheels; stepper motors at up
to 1000 steps/s, 1000 steps per wheel turn, so 0.1288 m/s and
2 x 0.1288 / 0.053 = 4.86 rad/s; eight TCRT1000 infrared proximity sensors
that see objects up to about 6 cm). Sensor directions (degrees from the
heading, counterclockwise): +-18, +-45, +-90, +-142, as in the Enki
simulator's e-puck model (``EPuck.cpp``), the common reference for them.
Each sensor is one beam from the robot's centre; range 0.1 m is the 35 mm
radius plus the 6 cm the sensors see (their response is not a distance but
a reflected intensity: a ranger with a 3 mm sigma is an approximation). The
steppers follow their commanded rate within milliseconds; no time constant
is published, 0.05 s is assumed. Tuned gains: speed kp 0.401, ki 25.60;
heading kp 0.761, kd 0.013.
"""

KOBUKI = RobotType(
    name="Kobuki", width=0.3515, length=0.3515, kv=0.7, kw=math.pi,
    tau_v=0.7 / 0.5, tau_w=math.pi / 3.5,
    ranger=RangerSpec(name="Asus Xtion PRO LIVE as a laser scan (simplified)",
                      fov=math.radians(58), beams=58, range=3.5, sigma=0.0175),
)
"""Yujin Robot Kobuki base, the TurtleBot2.

Sources: Kobuki specifications (Yujin Robot / kobuki.yujinrobot.com: 351.5 mm
diameter, modelled as a square of that side; maximum translational velocity
0.7 m/s, maximum rotational velocity 180 deg/s). The TurtleBot2's usual
depth camera, the Asus Xtion PRO LIVE (58 degree horizontal field of view,
0.8-3.5 m), is read as a laser scan as ``depthimage_to_laserscan`` does,
simplified to one beam per degree; its 0.8 m minimum range is not modelled.
The time constants are the maximum velocities over the acceleration limits
of Kobuki's own driver (``kobuki_driver`` ``AccelerationLimiter`` defaults:
0.5 m/s^2, 3.5 rad/s^2): ``tau_v`` = 1.4 s, ``tau_w`` = 0.898 s. Tuned
gains: speed kp 6.361, ki 4.710; heading kp 9.652, kd 2.604. The slow speed
plant saturates the actuator for speed steps above 0.21 x 0.7 m/s (see the
docs' robot models page).
"""

POINT = RobotType(
    name="point", width=0.01, length=0.01, kv=1.0, kw=2.0, tau_v=0.05, tau_w=0.05,
)
"""A generic near-point robot for quick tests: 1 cm square, 1 m/s, 2 rad/s, fast
lags (0.05 s), no ranger, no noise. Tuned gains: speed kp 0.052, ki 3.297;
heading kp 1.849, kd 0.033."""

BUILTIN_ROBOT_TYPES: dict[str, RobotType] = {
    t.name: t for t in (PIONEER_3AT, PIONEER_2DX, SWARMBOT, TURTLEBOT3_BURGER, EPUCK, KOBUKI,
                        POINT)
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



def builtin_robot_type(name: str) -> RobotType:
    """The built-in type called ``name`` (exact, else the one name equal ignoring case).

    Raises:
        ScenarioError: no such type; the message lists the known names.
    """
    if name in BUILTIN_ROBOT_TYPES:
        return BUILTIN_ROBOT_TYPES[name]
    folded = [t for n, t in BUILTIN_ROBOT_TYPES.items() if n.casefold() == name.casefold()]
    if len(folded) == 1:
        return folded[0]
    raise ScenarioError(f"unknown robot type {name!r} (expected one of "
                        f"{', '.join(BUILTIN_ROBOT_TYPES)})")
