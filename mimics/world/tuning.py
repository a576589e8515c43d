"""The rule that gives every robot type its default speed and heading gains.

Both loops are designed on the exact zero-order-hold discretisation of the
plant at the control period ``dt`` (0.1 s, the scenarios' default), since the
controller is sampled: a continuous design at ``dt`` comparable to the plant's
time constants would not give the response it promises.

**Speed loop (PI).** The plant ``v' = (-v + kv*u)/tau_v`` sampled at ``dt``
is ``v[k+1] = a*v[k] + kv*(1 - a)*u[k]`` with ``a = exp(-dt/tau_v)``. The PI
as the engine computes it, ``u[k] = kp*e[k] + ki*dt*(e[0] + ... + e[k])``,
is ``C(z) = ((kp + ki*dt)*z - kp) / (z - 1)``. Its zero is put on the
plant's pole (``kp / (kp + ki*dt) = a``) and the loop gain then sets the
one remaining closed-loop pole at ``p = exp(-dt/T_v)``::

    kp = a*(1 - p) / (kv*(1 - a)),      ki = (1 - p) / (kv*dt)

so that, while the actuator is not saturated, a speed step from one steady
state to another is exactly ``v[k] = r + (v0 - r)*p**k`` at the samples: a
first-order response of time constant ``T_v``, no overshoot.

**Heading loop (PD on the turn rate).** With the heading ``theta`` and turn
rate ``w`` as state, the sampled plant is linear, and ``u = kp*e - kd*w``
(``e`` the wrapped heading error) is a state feedback; ``kp`` and ``kd``
place both closed-loop poles at ``q = exp(-dt/T_h)`` (critically damped:
no overshoot while unsaturated). The plant integrates ``w``, so no integral
term is needed for a constant reference (``ki = 0``). A 90 degree turn
saturates the actuator of every built-in type for most of the turn; the
anti-windup and the double pole bring it in without overshoot (tested).

>>> kp, ki, kd = speed_gains(kv=1.0, tau_v=0.5)
>>> round(kp, 3), round(ki, 3), kd
(1.489, 3.297, 0.0)
"""

from __future__ import annotations

import math

DESIGN_DT = 0.1  # s: the control period the gains are designed for (the scenarios' default)
SPEED_TIME_CONSTANT = 0.25  # s: closed-loop T_v; 2% settling in 4*T_v = 1.0 s
HEADING_TIME_CONSTANT = 0.12  # s: closed-loop T_h of the heading loop's double pole


def speed_gains(kv: float, tau_v: float, dt: float = DESIGN_DT,
                time_constant: float = SPEED_TIME_CONSTANT) -> tuple[float, float, float]:
    """``(kp, ki, kd)`` of the speed PI: zero on the sampled plant pole, pole at exp(-dt/T).

    Args:
        kv: Actuator gain (m/s at full actuation).
        tau_v: Plant time constant (s).
        dt: Control period (s).
        time_constant: Wanted closed-loop time constant ``T_v`` (s).
    """
    a = math.exp(-dt / tau_v)
    p = math.exp(-dt / time_constant)
    return a * (1.0 - p) / (kv * (1.0 - a)), (1.0 - p) / (kv * dt), 0.0


def heading_gains(kw: float, tau_w: float, dt: float = DESIGN_DT,
                  time_constant: float = HEADING_TIME_CONSTANT) -> tuple[float, float, float]:
    """``(kp, ki, kd)`` of the heading loop: both sampled closed-loop poles at exp(-dt/T).

    The sampled plant, state ``(theta, w)`` and input ``u`` held over ``dt``::

        w[k+1]     = c*w[k] + kw*(1 - c)*u[k]                       c = exp(-dt/tau_w)
        theta[k+1] = theta[k] + tau_w*(1 - c)*w[k] + kw*(dt - tau_w*(1 - c))*u[k]

    With ``u = -kp*(theta - r) - kd*w`` the closed-loop characteristic
    polynomial is ``z**2 - trace*z + det``, whose trace and determinant are
    affine in ``kp, kd``; matching ``(z - q)**2`` is a 2x2 linear system.

    Args:
        kw: Actuator gain (rad/s at full actuation).
        tau_w: Plant time constant (s).
        dt: Control period (s).
        time_constant: Wanted closed-loop time constant ``T_h`` of the double pole (s).
    """
    c = math.exp(-dt / tau_w)
    q = math.exp(-dt / time_constant)
    b_theta, b_w = kw * (dt - tau_w * (1.0 - c)), kw * (1.0 - c)
    a_theta_w = tau_w * (1.0 - c)
    # trace = 1 + c - b_theta*kp - b_w*kd = 2q
    # det   = c - b_w*kd + (a_theta_w*b_w - c*b_theta)*kp = q**2
    m11, m12, r1 = b_theta, b_w, 1.0 + c - 2.0 * q
    m21, m22, r2 = a_theta_w * b_w - c * b_theta, -b_w, q * q - c
    det = m11 * m22 - m12 * m21
    kp = (r1 * m22 - m12 * r2) / det
    kd = (m11 * r2 - m21 * r1) / det
    return kp, 0.0, kd
