"""The closed loops (plant + PID) of every built-in robot type against closed forms.

Independent truths: the plant's exact zero-order-hold discretisation comes
from ``scipy.signal.cont2discrete`` (a matrix exponential), the sampled
closed loop's step response from ``scipy.signal.dstep`` on the z-domain
transfer function of plant and PI, the continuous limit from
``scipy.signal.step`` on the Laplace one; the engine's responses come from
``move_robots``, the function a simulation's step calls.
"""

import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import signal

from mimics.engine.responses import overshoot, settling_time, step_response
from mimics.world.robot_types import BUILTIN_ROBOT_TYPES, PIONEER_3AT, PidGains, RobotType
from mimics.world.tuning import (
    DESIGN_DT,
    HEADING_TIME_CONSTANT,
    SPEED_TIME_CONSTANT,
    heading_gains,
    speed_gains,
)

DT = DESIGN_DT
TYPES = list(BUILTIN_ROBOT_TYPES.values())
IDS = list(BUILTIN_ROBOT_TYPES)


def unsaturated_step(t: RobotType) -> float:
    """Half the top speed, or the largest step from rest whose first actuation stays within
    [-1, 1] (u0 = (kp + ki*dt) * r), whichever is smaller."""
    gains = t.speed_pid
    return min(0.5 * t.kv, 0.999 / (gains.kp + gains.ki * DT))


def sampled_speed_loop(t: RobotType, gains: PidGains, steps: int) -> np.ndarray:
    """The unit step response of plant and PI sampled at DT, from the z-domain transfer function."""
    (num_g, den_g) = signal.cont2discrete(([t.kv], [t.tau_v, 1.0]), DT, method="zoh")[:2]
    num_g, den_g = np.ravel(num_g), np.ravel(den_g)
    # u[k] = kp e[k] + ki dt sum_{j<=k} e[j]  ->  C(z) = ((kp + ki dt) z - kp) / (z - 1)
    num_c, den_c = [gains.kp + gains.ki * DT, -gains.kp], [1.0, -1.0]
    open_num, open_den = np.polymul(num_c, num_g), np.polymul(den_c, den_g)
    closed_den = np.polyadd(open_den, open_num)
    _, (y,) = signal.dstep((open_num, closed_den, DT), n=steps + 1)
    return np.ravel(y)


@pytest.mark.parametrize("robot_type", TYPES, ids=IDS)
def test_unsaturated_speed_step_and_stop_match_the_sampled_closed_loop(robot_type: RobotType
                                                                      ) -> None:
    r = unsaturated_step(robot_type)
    up = step_response(robot_type, r, 0.0, duration=3.0, dt=DT)
    stop = step_response(robot_type, 0.0, 0.0, start_speed=r, duration=3.0, dt=DT)
    assert np.all(np.abs(up.actuation[:-1, 0]) < 1.0)  # the test is of the linear loop
    unit = sampled_speed_loop(robot_type, robot_type.speed_pid, up.time.size - 1)
    np.testing.assert_allclose(up.speed, r * unit, atol=1e-9 * robot_type.kv)
    np.testing.assert_allclose(stop.speed, r * (1.0 - unit), atol=1e-9 * robot_type.kv)
    # the tuning rule's promise: a first-order response of time constant T_v at the samples
    np.testing.assert_allclose(up.speed, r * (1 - np.exp(-up.time / SPEED_TIME_CONSTANT)),
                               atol=1e-9 * robot_type.kv)


def test_the_sampled_closed_loop_form_holds_for_other_gains_too() -> None:
    """The former defaults (kp 2, ki 2): second order, slow, still the z-domain solution."""
    old = replace(PIONEER_3AT, speed_pid=PidGains(2.0, 2.0))
    up = step_response(old, 0.2, 0.0, duration=6.0)
    assert np.all(np.abs(up.actuation[:-1, 0]) < 1.0)
    np.testing.assert_allclose(up.speed, 0.2 * sampled_speed_loop(old, old.speed_pid, 60),
                               atol=1e-10)
    assert settling_time(up.speed, up.time, 0.2, 0.004) > 3.0  # the complaint


@pytest.mark.parametrize("robot_type", TYPES, ids=IDS)
def test_fast_sampling_approaches_the_continuous_laplace_solution(robot_type: RobotType) -> None:
    """At dt -> 0 the sampled PI is the continuous one: kv(kp s + ki) / (tau s^2 + (1 + kv kp) s
    + kv ki), whatever gains (here the type's own)."""
    gains, dt = robot_type.speed_pid, 0.001
    r = 0.1 * robot_type.kv / (gains.kp + gains.ki * DT + 1.0)  # stays unsaturated
    up = step_response(robot_type, r, 0.0, dt=dt, duration=2.0)
    kv, tau = robot_type.kv, robot_type.tau_v
    _, y = signal.step(([kv * gains.kp, kv * gains.ki], [tau, 1 + kv * gains.kp, kv * gains.ki]),
                       T=up.time)
    np.testing.assert_allclose(up.speed, r * y, atol=0.01 * r)


@pytest.mark.parametrize("robot_type", TYPES, ids=IDS)
def test_saturated_speed_follows_the_plants_own_exponential(robot_type: RobotType) -> None:
    """A reference beyond the top speed keeps u_v at 1: v = kv (1 - exp(-t / tau_v)), and the
    integral does not wind up (held: (kp + ki dt) * (r - v) > 1 keeps u_v saturated)."""
    gains = robot_type.speed_pid
    up = step_response(robot_type, robot_type.kv + 2.0 / (gains.kp + gains.ki * DT), 0.0,
                       duration=2.0)
    assert np.all(up.actuation[:-1, 0] == 1.0)
    np.testing.assert_allclose(up.speed, robot_type.kv * (1 - np.exp(-up.time / robot_type.tau_v)),
                               rtol=1e-12, atol=1e-15)


def test_a_step_that_saturates_then_follows_the_exponential_until_the_loop_takes_over() -> None:
    """Pioneer 3-AT, 0.8 m/s: saturated for the first samples (the plant's own exponential),
    then below 1 and monotone to the reference without overshoot."""
    up = step_response(PIONEER_3AT, 0.8, 0.0, duration=4.0)
    saturated = np.flatnonzero(up.actuation[:-1, 0] == 1.0)
    assert saturated.size >= 2 and np.all(np.diff(saturated) == 1) and saturated[0] == 0
    end = saturated[-1] + 1
    np.testing.assert_allclose(up.speed[: end + 1], 1 - np.exp(-up.time[: end + 1] / 0.5),
                               rtol=1e-12)
    assert np.all(np.diff(up.speed) >= -1e-12)
    assert overshoot(up.speed, 0.0, 0.8) == 0.0
    assert abs(up.speed[-1] - 0.8) < 0.002


@pytest.mark.parametrize("robot_type", TYPES, ids=IDS)
def test_speed_step_and_stop_settle_within_two_percent_in_1_5_s(robot_type: RobotType) -> None:
    r = unsaturated_step(robot_type)
    up = step_response(robot_type, r, 0.0, duration=4.0)
    stop = step_response(robot_type, 0.0, 0.0, start_speed=r, duration=4.0)
    assert settling_time(up.speed, up.time, r, 0.02 * r) <= 1.5
    assert settling_time(stop.speed, stop.time, 0.0, 0.02 * r) <= 1.5
    assert overshoot(up.speed, 0.0, r) <= 0.05
    assert overshoot(stop.speed, r, 0.0) <= 0.05


@pytest.mark.parametrize("direction", [1.0, -1.0])
@pytest.mark.parametrize("robot_type", TYPES, ids=IDS)
def test_a_90_degree_turn_settles_within_2_degrees_in_2_s(robot_type: RobotType,
                                                          direction: float) -> None:
    target = direction * math.pi / 2
    turn = step_response(robot_type, 0.0, target, duration=5.0)
    assert settling_time(turn.heading, turn.time, target, math.radians(2)) <= 2.0
    assert overshoot(turn.heading, 0.0, target) <= 0.05
    assert abs(turn.heading[-1] - target) < 1e-3  # the plant integrates: no steady error


@pytest.mark.parametrize("robot_type", TYPES, ids=IDS)
def test_unsaturated_heading_step_matches_the_state_space_closed_form(robot_type: RobotType
                                                                     ) -> None:
    """A small turn: x[k] = (A - B K)^k x[0] with A, B the plant's exact ZOH matrices (scipy);
    both closed-loop eigenvalues at exp(-dt / T_h), as the rule places them."""
    gains = robot_type.heading_pid
    tau, kw = robot_type.tau_w, robot_type.kw
    # state (theta, w): theta' = w, w' = (-w + kw u) / tau
    a, b, *_ = signal.cont2discrete((np.array([[0, 1], [0, -1 / tau]]), np.array([[0], [kw / tau]]),
                                     np.eye(2), np.zeros((2, 1))), DT, method="zoh")
    k_gain = np.array([[gains.kp, gains.kd]])
    closed = a - b @ k_gain
    np.testing.assert_allclose(np.linalg.eigvals(closed), [math.exp(-DT / 0.12)] * 2, rtol=1e-5)
    target = 0.02 / (gains.kp * 1.5)  # small enough for |u| < 1 throughout
    turn = step_response(robot_type, 0.0, target, duration=2.0)
    assert np.all(np.abs(turn.actuation[:-1, 1]) < 1.0)
    state = np.array([-target, 0.0])  # the error coordinates: theta - target, w
    for k in range(turn.time.size):
        assert turn.heading[k] - target == pytest.approx(state[0], abs=1e-12)
        assert turn.turn_rate[k] == pytest.approx(state[1], abs=1e-12)
        state = closed @ state


def test_gains_are_the_types_own_unless_given() -> None:
    custom = RobotType(name="slow", width=0.3, length=0.3, kv=0.5, kw=1.0, tau_v=1.0, tau_w=0.5,
                       speed_pid=PidGains(1.0, 0.5), heading_pid=PidGains(3.0))
    assert custom.speed_pid == PidGains(1.0, 0.5) and custom.heading_pid == PidGains(3.0)
    tuned = RobotType(name="slow", width=0.3, length=0.3, kv=0.5, kw=1.0, tau_v=1.0, tau_w=0.5)
    up = step_response(tuned, 0.1, 0.0)
    np.testing.assert_allclose(up.speed, 0.1 * (1 - np.exp(-up.time / SPEED_TIME_CONSTANT)),
                               atol=1e-12)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(kv=st.floats(0.05, 3.0), tau=st.floats(0.01, 3.0), dt=st.floats(0.01, 0.3),
       time_constant=st.floats(0.05, 2.0))
def test_the_speed_rule_places_the_sampled_closed_loop_pole_for_any_plant(
        kv: float, tau: float, dt: float, time_constant: float) -> None:
    """The closed loop's characteristic polynomial (z-1)(z-a) + b((kp+ki dt)z - kp) has its
    roots at exp(-dt/T) and on the plant pole a (cancelled by the PI's zero)."""
    kp, ki, _ = speed_gains(kv, tau, dt=dt, time_constant=time_constant)
    a, b = math.exp(-dt / tau), kv * (1 - math.exp(-dt / tau))
    characteristic = np.polyadd(np.polymul([1, -1], [1, -a]), [b * (kp + ki * dt), -b * kp])
    np.testing.assert_allclose(characteristic,
                               np.poly([a, math.exp(-dt / time_constant)]), atol=1e-9)
    assert kp * (1 - a) / a == pytest.approx(ki * dt)  # the zero kp / (kp + ki dt) is a


@settings(max_examples=60, deadline=None, derandomize=True)
@given(kw=st.floats(0.2, 6.0), tau=st.floats(0.01, 2.0), dt=st.floats(0.01, 0.3))
def test_the_heading_rule_places_both_sampled_poles_for_any_plant(kw: float, tau: float,
                                                                 dt: float) -> None:
    kp, ki, kd = heading_gains(kw, tau, dt=dt)
    a, b, *_ = signal.cont2discrete((np.array([[0, 1], [0, -1 / tau]]), np.array([[0], [kw / tau]]),
                                     np.eye(2), np.zeros((2, 1))), dt, method="zoh")
    closed = a - b @ np.array([[kp, kd]])
    q = math.exp(-dt / HEADING_TIME_CONSTANT)
    # a double pole: the characteristic polynomial is (z - q)^2
    np.testing.assert_allclose(np.poly(closed), [1.0, -2 * q, q * q], atol=1e-8)
    assert ki == 0.0
