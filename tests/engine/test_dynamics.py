"""Dynamics against closed forms (SPEC section 2)."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from mimics.engine.dynamics import (
    Plant,
    advance_pose,
    integrate_velocities,
    pid_actuation,
    wrap_angle,
)

KV, KW, TAU_V, TAU_W = 1.0, 1.0, 0.5, 0.2


def plant(n: int = 1) -> Plant:
    return Plant(np.full(n, KV), np.full(n, KW), np.full(n, TAU_V), np.full(n, TAU_W))


@pytest.mark.parametrize("dt", [0.1, 0.05, 0.3])
@pytest.mark.parametrize("u", [1.0, 0.4, -0.7])
def test_open_loop_step_response_matches_closed_form(dt: float, u: float) -> None:
    v = np.zeros(1)
    w = np.zeros(1)
    pose = np.zeros((1, 3))
    p = plant()
    for k in range(1, 60):
        motion = integrate_velocities(v, w, np.array([u]), np.zeros(1), p, dt)
        v, w = motion.v, motion.w
        pose = advance_pose(pose, motion.distance, motion.turn)
        t = k * dt
        expected_v = KV * u * (1 - math.exp(-t / TAU_V))
        expected_x = KV * u * (t - TAU_V * (1 - math.exp(-t / TAU_V)))
        assert v[0] == pytest.approx(expected_v, abs=1e-12)
        assert pose[0, 0] == pytest.approx(expected_x, abs=1e-10)
        assert pose[0, 1] == 0.0


def test_turning_in_place_matches_closed_form() -> None:
    dt, u = 0.1, 0.8
    v, w = np.zeros(1), np.zeros(1)
    pose = np.array([[1.0, 2.0, 0.0]])
    for k in range(1, 40):
        motion = integrate_velocities(v, w, np.zeros(1), np.array([u]), plant(), dt)
        v, w = motion.v, motion.w
        pose = advance_pose(pose, motion.distance, motion.turn)
        t = k * dt
        theta = KW * u * (t - TAU_W * (1 - math.exp(-t / TAU_W)))
        assert w[0] == pytest.approx(KW * u * (1 - math.exp(-t / TAU_W)), abs=1e-12)
        assert pose[0, 2] == pytest.approx(wrap_angle(theta), abs=1e-10)
        assert pose[0, :2].tolist() == [1.0, 2.0]


def test_steady_turn_follows_the_exact_circle() -> None:
    u_v, u_w, dt = 0.5, 0.25, 0.1
    v, w = np.array([KV * u_v]), np.array([KW * u_w])  # already at steady state
    pose = np.zeros((1, 3))
    radius = v[0] / w[0]
    for k in range(1, 100):
        motion = integrate_velocities(v, w, np.array([u_v]), np.array([u_w]), plant(), dt)
        v, w = motion.v, motion.w
        pose = advance_pose(pose, motion.distance, motion.turn)
        angle = w[0] * k * dt
        assert pose[0, 0] == pytest.approx(radius * math.sin(angle), abs=1e-9)
        assert pose[0, 1] == pytest.approx(radius * (1 - math.cos(angle)), abs=1e-9)


def test_saturated_pid_does_not_wind_up() -> None:
    gains = np.array([[2.0, 2.0, 0.0]])
    integral = np.zeros(1)
    for _ in range(100):  # a large error keeps the output saturated
        u, integral = pid_actuation(np.array([5.0]), np.zeros(1), integral, gains, 0.1)
        assert u[0] == 1.0
    assert integral[0] == 0.0
    # An error of the other sign integrates again at once.
    u, integral = pid_actuation(np.array([-0.1]), np.zeros(1), integral, gains, 0.1)
    assert integral[0] == pytest.approx(-0.01)
    assert u[0] == pytest.approx(2 * -0.1 + 2 * -0.01)


def test_derivative_acts_on_the_measurement() -> None:
    gains = np.array([[0.0, 0.0, 0.5]])
    u, _ = pid_actuation(np.array([0.0]), np.array([0.4]), np.zeros(1), gains, 0.1)
    assert u[0] == pytest.approx(-0.2)


@given(st.floats(-1e4, 1e4, allow_nan=False))
def test_wrap_angle_range_and_equivalence(angle: float) -> None:
    wrapped = wrap_angle(angle)
    assert -math.pi < wrapped <= math.pi
    assert math.isclose(math.cos(wrapped), math.cos(angle), abs_tol=1e-9)
    assert math.isclose(math.sin(wrapped), math.sin(angle), abs_tol=1e-9)
