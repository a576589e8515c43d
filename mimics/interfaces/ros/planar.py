"""The meaning of the bridge's messages, free of any ROS library: shared by ROS 1 and ROS 2.

Both transports (``rospy`` in :mod:`~mimics.interfaces.ros.conversion`, Cyclone
DDS in :mod:`mimics.interfaces.ros2.conversion`) fill their own message classes
from what is computed here: stamps in whole nanoseconds, a yaw as a
quaternion, the planar covariance in a 6x6, the ``map -> odom`` correction,
a scan's angles, ranges and intensities, and a velocity command checked and turned into
the two references a mimics robot follows.

>>> sec_nanosec(1.25)
(1, 250000000)
>>> [round(value, 6) for value in yaw_quaternion(math.pi)]
[0.0, 0.0, 1.0, 0.0]
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from mimics.interfaces.ros.inbox import Command

PLANAR = [0, 1, 5]  # x, y and yaw among a 6x6 covariance's x, y, z, roll, pitch, yaw


class BadCommand(ValueError):
    """A command message that cannot be used (its text says why)."""


def nanoseconds(seconds: float) -> int:
    """Simulated seconds in whole nanoseconds (rounded: no float truncation)."""
    return round(seconds * 1e9)


def sec_nanosec(seconds: float) -> tuple[int, int]:
    """Simulated seconds as ``(sec, nanosec)``, the fields of a ROS time."""
    sec, nanosec = divmod(nanoseconds(seconds), 1_000_000_000)
    return sec, nanosec


def step_of(stamp_seconds: float, dt: float) -> int:
    """The step whose time is ``stamp_seconds`` (the nearest whole number of steps)."""
    return round(stamp_seconds / dt)


def yaw_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """``(x, y, z, w)`` of a rotation of ``yaw`` radians about z."""
    return 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)


def quaternion_yaw(q: Any) -> float:
    """The rotation about z of a quaternion (anything with ``x``, ``y``, ``z``, ``w``)."""
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


def covariance_6x6(planar: np.ndarray) -> list[float]:
    """The 36 values of a 6x6 covariance holding the 3x3 covariance of ``(x, y, theta)``
    in rows and columns x, y and yaw (0, 1 and 5); 0 elsewhere."""
    values = [0.0] * 36
    for row, cells in zip(PLANAR, np.asarray(planar).tolist(), strict=True):
        for column, value in zip(PLANAR, cells, strict=True):
            values[6 * row + column] = value
    return values


def odom_correction(pose: np.ndarray, odometry: np.ndarray) -> tuple[float, float, float]:
    """``map -> odom`` as ``(x, y, yaw)``: ``T(pose) * T(odometry)^-1`` (REP 105).

    ``odometry`` is the odometer's pose in the odom frame, ``pose`` the
    measured pose in ``map``: the correction puts the body at ``pose``, as a
    localiser would publish it.
    """
    px, py, ptheta = (float(value) for value in pose)
    ox, oy, otheta = (float(value) for value in odometry)
    yaw = ptheta - otheta
    cos, sin = math.cos(yaw), math.sin(yaw)
    return px - (cos * ox - sin * oy), py - (sin * ox + cos * oy), yaw


def scan_values(ranges: np.ndarray, hit: np.ndarray, angles: np.ndarray, max_range: float,
                no_return_at_max: bool = False) -> tuple[float, float, float, np.ndarray]:
    """``(angle_min, angle_max, angle_increment, ranges)`` of a ranger reading.

    Beams that hit nothing read ``+inf`` (REP 117), or ``max_range`` with
    ``no_return_at_max`` (what stage_ros publishes). ``angles`` are the
    ranger's beam angles (right to left, evenly spread).
    """
    increment = float(angles[1] - angles[0]) if len(angles) > 1 else 0.0
    values = np.where(hit, ranges, float(max_range) if no_return_at_max else np.inf)
    return float(angles[0]), float(angles[-1]), increment, values


def scan_intensities(hit: np.ndarray) -> np.ndarray:
    """stage_ros' intensities: 1.0 where a beam hit something, 0.0 where it did not.

    Stage gives a beam the ``ranger_return`` of the model it hit (1 unless a
    world file sets it, and every mimics wall and robot is such a model) and
    0 with no return.
    """
    return np.where(hit, 1.0, 0.0)


def array_command(data: list[float], dt: float) -> Command:
    """``cmd``'s ``data``: ``[speed_ref, heading_ref]`` or ``[speed_ref, heading_ref, stamp]``.

    ``speed_ref`` in m/s, ``heading_ref`` an absolute heading in ``map`` (rad);
    ``stamp`` is the ``header.stamp`` (in seconds) of the ``odom`` message the
    reference answers, which ties it to that step in lockstep mode.

    Raises:
        BadCommand: on a wrong length or a value that is not finite.
    """
    if len(data) not in (2, 3):
        raise BadCommand(f"cmd: expected data = [speed_ref, heading_ref] or [speed_ref, "
                         f"heading_ref, stamp], got {len(data)} values")
    names = ("speed_ref", "heading_ref", "stamp")
    for name, value in zip(names, data, strict=False):
        if not math.isfinite(value):
            raise BadCommand(f"cmd: {name} must be a finite number, got {value}")
    step = step_of(data[2], dt) if len(data) == 3 else None
    if step is not None and step < 0:
        raise BadCommand(f"cmd: stamp must not be negative, got {data[2]}")
    return Command("reference", float(data[0]), float(data[1]), step)


def twist_command(speed: float, turn: float) -> Command:
    """``cmd_vel``'s ``linear.x`` (m/s) and ``angular.z`` (rad/s) as a command.

    Raises:
        BadCommand: when either is not finite.
    """
    if not (math.isfinite(speed) and math.isfinite(turn)):
        raise BadCommand(f"cmd_vel: linear.x and angular.z must be finite numbers, got "
                         f"{speed} and {turn}")
    return Command("twist", float(speed), float(turn), None)


def twist_to_references(speed: float, turn_rate: float, heading: float, kw: float,
                        heading_kp: float, heading_kd: float) -> tuple[float, float]:
    """Turn a velocity command into the two references the robot's PID loops follow.

    The speed reference is the commanded speed. The heading reference leads
    the measured heading by the error at which the heading loop turns at the
    commanded rate ``w`` in steady state: with ``w' = (-w + kw*u_w)/tau_w`` and
    ``u_w = kp*error - kd*w`` (the D term acts on the measured rate) that is
    ``error = w*(1 + kw*kd) / (kw*kp)``, exact for heading loops without an
    integral term, as the built-in types have. The rate is first limited to
    the robot's maximum, ``kw``.
    """
    rate = max(-kw, min(kw, turn_rate))
    lead = rate * (1.0 + kw * heading_kd) / (kw * heading_kp) if heading_kp > 0 else 0.0
    return speed, heading + lead
