"""One robot's closed-loop responses to speed and heading references, by the engine itself.

The responses are stepped with :func:`mimics.engine.dynamics.move_robots`,
the very function a simulation's step calls, so a plot or a test of them
shows what robots in a run do (the PID loops, saturation, anti-windup and
the exact zero-order-hold integration), not a copy of it.

>>> from mimics.world.robot_types import PIONEER_3AT
>>> r = step_response(PIONEER_3AT, speed_ref=0.4, heading_ref=0.0, duration=1.0)
>>> round(float(r.speed[-1]), 3)
0.393
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from mimics.engine.dynamics import move_robots
from mimics.world.robot_types import RobotType


class Response(NamedTuple):
    """Samples at ``time`` (``steps + 1`` of them, the first the initial state)."""

    time: np.ndarray
    speed: np.ndarray  # m/s
    turn_rate: np.ndarray  # rad/s
    heading: np.ndarray  # rad, unwrapped (sum of the turns)
    actuation: np.ndarray  # (steps + 1, 2): u_v, u_w applied from each sample on (last: NaN)


def step_response(robot_type: RobotType, speed_ref: float, heading_ref: float, *,
                  start_speed: float = 0.0, dt: float = 0.1, duration: float = 3.0) -> Response:
    """A robot at rest, heading 0 (or cruising at ``start_speed``), given constant references.

    Args:
        robot_type: The robot's type (plant and gains).
        speed_ref: Speed reference from time 0 on (m/s).
        heading_ref: Heading reference from time 0 on (rad).
        start_speed: Initial speed, held before time 0 by the speed loop in
            steady state (its integral term holds ``start_speed / kv``; a loop
            without integral term just starts from that speed); 0: at rest.
        dt: Control period (s).
        duration: Simulated time (s).
    """
    steps = round(duration / dt)
    pose, velocity = np.zeros((1, 3)), np.array([[start_speed, 0.0]])
    acceleration, actuation = np.zeros((1, 2)), np.zeros((1, 2))
    reference = np.array([[speed_ref, heading_ref]])
    integral = np.zeros((1, 2))
    sp, hp = robot_type.speed_pid, robot_type.heading_pid
    assert sp is not None and hp is not None  # set by RobotType
    if start_speed and sp.ki:
        integral[0, 0] = start_speed / robot_type.kv / sp.ki
    speed_gains = np.array([[sp.kp, sp.ki, sp.kd]])
    heading_gains = np.array([[hp.kp, hp.ki, hp.kd]])
    plant = [np.array([x], dtype=np.float64) for x in (robot_type.kv, robot_type.kw,
                                                       robot_type.tau_v, robot_type.tau_w)]
    rows = np.zeros(1, dtype=np.int64)
    path, distance, turn = np.zeros(1), np.zeros(1), np.zeros(1)
    speed, turn_rate, heading = (np.empty(steps + 1) for _ in range(3))
    applied = np.full((steps + 1, 2), math.nan)
    speed[0], turn_rate[0], heading[0] = start_speed, 0.0, 0.0
    for k in range(steps):
        move_robots(rows, pose, velocity, acceleration, reference, integral, actuation, path,
                    speed_gains, heading_gains, *plant, float(dt), distance, turn)
        speed[k + 1], turn_rate[k + 1] = velocity[0]
        heading[k + 1] = heading[k] + turn[0]
        applied[k] = actuation[0]
    return Response(np.arange(steps + 1) * dt, speed, turn_rate, heading, applied)


def settling_time(values: np.ndarray, time: np.ndarray, target: float, band: float) -> float:
    """The first sample time from which ``values`` stay within ``band`` of ``target``."""
    outside = np.flatnonzero(np.abs(values - target) > band)
    if outside.size == 0:
        return float(time[0])
    if outside[-1] + 1 >= time.size:
        return math.inf
    return float(time[outside[-1] + 1])


def overshoot(values: np.ndarray, start: float, target: float) -> float:
    """The largest excursion beyond ``target``, as a fraction of the step ``target - start``."""
    step = target - start
    if step == 0:
        return 0.0
    return max(0.0, float(np.max((values - target) / step)))


class StepFigures(NamedTuple):
    """The three standard responses of a type: a speed step, a stop, a 90 degree turn."""

    speed_ref: float  # m/s, of the step and of the cruise the stop starts from
    speed_step: Response
    stop: Response
    turn: Response


def standard_responses(robot_type: RobotType, *, dt: float = 0.1,
                       duration: float = 3.0) -> StepFigures:
    """A speed step from rest, a stop from that speed, a 90 degree turn from rest.

    The speed is half the top speed, or less where that would saturate the
    actuator at the first sample (the first actuation of a step ``r`` from
    rest is ``(kp + ki*dt) * r``, before the D term which acts on the
    measured rate): the loop's own response, within the actuator limits.
    """
    gains = robot_type.speed_pid
    assert gains is not None  # set by RobotType
    linear = 0.999 / (gains.kp + gains.ki * dt) if gains.kp + gains.ki * dt > 0 else math.inf
    speed = min(0.5 * robot_type.kv, linear)
    return StepFigures(
        speed,
        step_response(robot_type, speed, 0.0, dt=dt, duration=duration),
        step_response(robot_type, 0.0, 0.0, start_speed=speed, dt=dt, duration=duration),
        step_response(robot_type, 0.0, math.pi / 2, dt=dt, duration=duration),
    )
