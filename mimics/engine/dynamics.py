"""Second-order unicycle dynamics and the two PID loops (paper section 3.1).

The velocity states follow first-order lags driven by the saturated actuators
``u_v, u_w``; with the actuators held over a step (zero-order hold) they are
integrated exactly, and so are the distance travelled and the angle turned.
The pose then moves along the circular arc that covers that distance while
turning that angle, which is exact for straight motion, turning in place and
steady turning, and consistent with the velocities always.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np


class Plant(NamedTuple):
    """Per-robot dynamics parameters, arrays of shape ``(n,)``."""

    kv: np.ndarray
    kw: np.ndarray
    tau_v: np.ndarray
    tau_w: np.ndarray


class PidArrays(NamedTuple):
    """Per-robot PID gains ``(n, 3)`` as ``kp, ki, kd`` columns, for speed and heading."""

    speed: np.ndarray
    heading: np.ndarray


def wrap_angle(angle: np.ndarray | float) -> np.ndarray | float:
    """Wrap angles to (-pi, pi]."""
    wrapped = np.mod(np.asarray(angle) + np.pi, 2 * np.pi) - np.pi
    wrapped = np.where(wrapped == -np.pi, np.pi, wrapped)
    return wrapped if wrapped.ndim else float(wrapped)


def pid_actuation(error: np.ndarray, rate: np.ndarray, integral: np.ndarray,
                  gains: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """One PID update, saturated to [-1, 1], with conditional-integration anti-windup.

    ``rate`` is the measured derivative of the controlled quantity; the D term
    acts on it (not on the error) so a jump of the reference gives no kick.
    Returns the actuation and the new integral. The integral only accumulates
    while the output is unsaturated or the error drives it back from the limit.
    """
    kp, ki, kd = gains[:, 0], gains[:, 1], gains[:, 2]
    candidate = integral + error * dt
    raw = kp * error + ki * candidate - kd * rate
    actuation = np.minimum(np.maximum(raw, -1.0), 1.0)  # = np.clip, at half the cost
    saturated = raw != actuation
    winding_up = saturated & (np.sign(error) == np.sign(raw))
    new_integral = np.where(winding_up, integral, candidate)
    return actuation, new_integral


class Motion(NamedTuple):
    """Result of integrating one step: new velocities and the exact increments."""

    v: np.ndarray
    w: np.ndarray
    distance: np.ndarray  # signed distance travelled along the path
    turn: np.ndarray  # angle turned


def integrate_velocities(v: np.ndarray, w: np.ndarray, u_v: np.ndarray, u_w: np.ndarray,
                         plant: Plant, dt: float) -> Motion:
    """Exact zero-order-hold solution of the two first-order lags over ``dt``."""
    decay_v = np.exp(-dt / plant.tau_v)
    decay_w = np.exp(-dt / plant.tau_w)
    target_v = plant.kv * u_v
    target_w = plant.kw * u_w
    new_v = target_v + (v - target_v) * decay_v
    new_w = target_w + (w - target_w) * decay_w
    distance = target_v * dt + (v - target_v) * plant.tau_v * (1.0 - decay_v)
    turn = target_w * dt + (w - target_w) * plant.tau_w * (1.0 - decay_w)
    return Motion(new_v, new_w, distance, turn)


def advance_pose(pose: np.ndarray, distance: np.ndarray, turn: np.ndarray) -> np.ndarray:
    """Move ``(n, 3)`` poses along arcs of given length and turn; returns new poses."""
    x, y, theta = pose[:, 0], pose[:, 1], pose[:, 2]
    new_theta = theta + turn
    straight = np.abs(turn) < 1e-9
    safe_turn = np.where(straight, 1.0, turn)
    # Chord of an arc: exact for constant curvature; midpoint heading when straight.
    dx_arc = distance / safe_turn * (np.sin(new_theta) - np.sin(theta))
    dy_arc = -distance / safe_turn * (np.cos(new_theta) - np.cos(theta))
    mid = theta + 0.5 * turn
    dx = np.where(straight, distance * np.cos(mid), dx_arc)
    dy = np.where(straight, distance * np.sin(mid), dy_arc)
    out = np.empty_like(pose)
    out[:, 0] = x + dx
    out[:, 1] = y + dy
    out[:, 2] = wrap_angle(new_theta)
    return out
