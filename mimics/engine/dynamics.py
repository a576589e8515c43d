"""Second-order unicycle dynamics and the two PID loops (paper section 3.1).

The velocity states follow first-order lags driven by the saturated actuators
``u_v, u_w``; with the actuators held over a step (zero-order hold) they are
integrated exactly, and so are the distance travelled and the angle turned.
The pose then moves along the circular arc that covers that distance while
turning that angle, which is exact for straight motion, turning in place and
steady turning, and consistent with the velocities always.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.compiling.kernel_options import INNER

TAU = 2.0 * math.pi


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


@njit(cache=True)
def _wrap(angle: float) -> float:
    """One angle wrapped to (-pi, pi]."""
    wrapped = (angle + math.pi) % TAU - math.pi
    return math.pi if wrapped == -math.pi else wrapped


@njit(**INNER)
def _pid(error: float, rate: float, integral: float, kp: float, ki: float, kd: float,
         dt: float) -> tuple[float, float]:
    """One PID update of one loop: ``(actuation, new integral)``."""
    candidate = integral + error * dt
    raw = kp * error + ki * candidate - kd * rate
    actuation = smaller(larger(raw, -1.0), 1.0)
    # conditional integration: hold the integral while saturated and pushing further
    if raw != actuation and np.sign(error) == np.sign(raw):
        return actuation, integral
    return actuation, candidate


@njit(**INNER)
def _lag(value: float, target: float, tau: float, dt: float) -> tuple[float, float]:
    """A first-order lag toward ``target`` over ``dt``: ``(new value, its integral)``."""
    decay = math.exp(-dt / tau)
    return (target + (value - target) * decay,
            target * dt + (value - target) * tau * (1.0 - decay))


@njit(**INNER)
def _arc(x: float, y: float, theta: float, distance: float,
         turn: float) -> tuple[float, float, float]:
    """The pose after moving ``distance`` along an arc that turns ``turn``."""
    new_theta = theta + turn
    if abs(turn) < 1e-9:  # straight: the chord along the midpoint heading
        mid = theta + 0.5 * turn
        return x + distance * math.cos(mid), y + distance * math.sin(mid), _wrap(new_theta)
    radius = distance / turn
    return (x + radius * (math.sin(new_theta) - math.sin(theta)),
            y - radius * (math.cos(new_theta) - math.cos(theta)), _wrap(new_theta))


@njit(cache=True)
def _wrap_all(angles: np.ndarray) -> np.ndarray:
    out = np.empty_like(angles)
    for i in range(angles.shape[0]):
        out[i] = _wrap(angles[i])
    return out


def wrap_angle(angle: np.ndarray | float) -> np.ndarray | float:
    """Wrap angles to (-pi, pi]."""
    values = np.asarray(angle, dtype=np.float64)
    if values.ndim == 0:
        return _wrap(float(values))
    return _wrap_all(values.ravel()).reshape(values.shape)


@njit(cache=True)
def _pid_all(error: np.ndarray, rate: np.ndarray, integral: np.ndarray, gains: np.ndarray,
             dt: float) -> tuple[np.ndarray, np.ndarray]:
    actuation, new_integral = np.empty_like(error), np.empty_like(error)
    for i in range(error.shape[0]):
        actuation[i], new_integral[i] = _pid(error[i], rate[i], integral[i], gains[i, 0],
                                             gains[i, 1], gains[i, 2], dt)
    return actuation, new_integral


def pid_actuation(error: np.ndarray, rate: np.ndarray, integral: np.ndarray,
                  gains: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """One PID update, saturated to [-1, 1], with conditional-integration anti-windup.

    ``rate`` is the measured derivative of the controlled quantity; the D term
    acts on it (not on the error) so a jump of the reference gives no kick.
    Returns the actuation and the new integral. The integral only accumulates
    while the output is unsaturated or the error drives it back from the limit.
    """
    as_float = [np.ascontiguousarray(a, dtype=np.float64) for a in (error, rate, integral)]
    return _pid_all(*as_float, np.ascontiguousarray(gains, dtype=np.float64), float(dt))


class Motion(NamedTuple):
    """Result of integrating one step: new velocities and the exact increments."""

    v: np.ndarray
    w: np.ndarray
    distance: np.ndarray  # signed distance travelled along the path
    turn: np.ndarray  # angle turned


@njit(cache=True)
def _lags(v: np.ndarray, w: np.ndarray, u_v: np.ndarray, u_w: np.ndarray, kv: np.ndarray,
          kw: np.ndarray, tau_v: np.ndarray, tau_w: np.ndarray, dt: float
          ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    n = v.shape[0]
    new_v, new_w, distance, turn = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    for i in range(n):
        new_v[i], distance[i] = _lag(v[i], kv[i] * u_v[i], tau_v[i], dt)
        new_w[i], turn[i] = _lag(w[i], kw[i] * u_w[i], tau_w[i], dt)
    return new_v, new_w, distance, turn


def integrate_velocities(v: np.ndarray, w: np.ndarray, u_v: np.ndarray, u_w: np.ndarray,
                         plant: Plant, dt: float) -> Motion:
    """Exact zero-order-hold solution of the two first-order lags over ``dt``."""
    arrays = [np.ascontiguousarray(a, dtype=np.float64) for a in (v, w, u_v, u_w, *plant)]
    return Motion(*_lags(*arrays, float(dt)))


@njit(cache=True)
def _arcs(pose: np.ndarray, distance: np.ndarray, turn: np.ndarray) -> np.ndarray:
    out = np.empty_like(pose)
    for i in range(pose.shape[0]):
        out[i, 0], out[i, 1], out[i, 2] = _arc(pose[i, 0], pose[i, 1], pose[i, 2], distance[i],
                                               turn[i])
    return out


def advance_pose(pose: np.ndarray, distance: np.ndarray, turn: np.ndarray) -> np.ndarray:
    """Move ``(n, 3)`` poses along arcs of given length and turn; returns new poses."""
    return _arcs(np.ascontiguousarray(pose, dtype=np.float64),
                 np.ascontiguousarray(distance, dtype=np.float64),
                 np.ascontiguousarray(turn, dtype=np.float64))


@njit(cache=True)
def move_robots(rows: np.ndarray, pose: np.ndarray, velocity: np.ndarray,
                acceleration: np.ndarray, reference: np.ndarray, pid_integral: np.ndarray,
                actuation: np.ndarray, path_length: np.ndarray, speed_gains: np.ndarray,
                heading_gains: np.ndarray, kv: np.ndarray, kw: np.ndarray, tau_v: np.ndarray,
                tau_w: np.ndarray, dt: float, distance: np.ndarray, turn: np.ndarray) -> None:
    """One step of both PID loops and the dynamics for robots ``rows``, in place.

    The same arithmetic as ``pid_actuation``, ``integrate_velocities`` and
    ``advance_pose`` one after another; ``distance`` and ``turn`` receive
    each moved robot's increments (for the odometer).
    """
    for i in rows:
        v, w = velocity[i, 0], velocity[i, 1]
        # elements, not row views: a view per robot would be reference-counted
        u_v, integral_v = _pid(reference[i, 0] - v, acceleration[i, 0], pid_integral[i, 0],
                               speed_gains[i, 0], speed_gains[i, 1], speed_gains[i, 2], dt)
        u_w, integral_w = _pid(_wrap(reference[i, 1] - pose[i, 2]), w, pid_integral[i, 1],
                               heading_gains[i, 0], heading_gains[i, 1], heading_gains[i, 2],
                               dt)
        new_v, distance[i] = _lag(v, kv[i] * u_v, tau_v[i], dt)
        new_w, turn[i] = _lag(w, kw[i] * u_w, tau_w[i], dt)
        actuation[i, 0], actuation[i, 1] = u_v, u_w
        pid_integral[i, 0], pid_integral[i, 1] = integral_v, integral_w
        acceleration[i, 0] = (new_v - v) / dt
        acceleration[i, 1] = (new_w - w) / dt
        velocity[i, 0], velocity[i, 1] = new_v, new_w
        pose[i, 0], pose[i, 1], pose[i, 2] = _arc(pose[i, 0], pose[i, 1], pose[i, 2],
                                                  distance[i], turn[i])
        path_length[i] += abs(distance[i])
