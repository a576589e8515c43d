"""The odometer as ROS means it: its pose in an ``odom`` frame, and that pose's covariance.

Pure NumPy (no ROS): the bridge's ``odometry`` module publishes what this computes.

**The odom frame** of a robot is its start pose in ``map``: the odometer's
pose ``q`` (the engine keeps it in map coordinates, starting at the start
pose ``s``) is published as ``T(s)^-1 * T(q)``, so it reads ``(0, 0, 0)`` at
``t = 0`` and then drifts with the odometer's accumulated noise.

**The covariance** of that pose follows the robot type's odometry noise
(``sigma_translation`` metres per metre travelled, ``sigma_rotation``
radians per radian turned, drawn each step on the step's increment; see
``mimics.world.robot_types.OdometryNoise``), propagated step by step to
first order, as an odometry-only EKF predicts it. Step ``k`` takes the pose
``(x, y, theta)`` to ``(x', y', theta')``; its increment as the odometer
measured it is the turn ``d_theta = wrap(theta' - theta)`` and the signed
distance ``d = ((x'-x) cos(phi) + (y'-y) sin(phi))`` along the mid heading
``phi = theta + d_theta/2``. With the first-order motion model ``x' = x + d
cos(phi)``, ``y' = y + d sin(phi)``, ``theta' = theta + d_theta``::

    F = [[1, 0, -d sin(phi)],     G = [[cos(phi), -d/2 sin(phi)],
         [0, 1,  d cos(phi)],          [sin(phi),  d/2 cos(phi)],
         [0, 0,  1         ]]          [0,         1           ]]

    Q = diag((sigma_translation * |d|)^2, (sigma_rotation * |d_theta|)^2)

    P_0 = 0,    P_k = F P_(k-1) F^T + G Q G^T

in the ``odom`` frame's coordinates. A robot that does not move keeps its
covariance (its odometer draws no noise then); a type without odometry
noise keeps 0.
"""

from __future__ import annotations

import numpy as np


def wrap(angle: np.ndarray) -> np.ndarray:
    """Angles wrapped into ``[-pi, pi)``."""
    return (angle + np.pi) % (2.0 * np.pi) - np.pi


def relative_poses(start: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """``(n, 3)`` poses ``T(start)^-1 * T(pose)``, row by row: ``poses`` seen from ``start``."""
    dx, dy = poses[:, 0] - start[:, 0], poses[:, 1] - start[:, 1]
    cos, sin = np.cos(start[:, 2]), np.sin(start[:, 2])
    return np.column_stack((cos * dx + sin * dy, -sin * dx + cos * dy,
                            wrap(poses[:, 2] - start[:, 2])))


def propagate(covariance: np.ndarray, before: np.ndarray, after: np.ndarray,
              sigma_translation: np.ndarray, sigma_rotation: np.ndarray) -> np.ndarray:
    """``(n, 3, 3)`` covariances after one step from poses ``before`` to ``after`` (see above)."""
    turn = wrap(after[:, 2] - before[:, 2])
    phi = before[:, 2] + turn / 2.0
    cos, sin = np.cos(phi), np.sin(phi)
    distance = (after[:, 0] - before[:, 0]) * cos + (after[:, 1] - before[:, 1]) * sin
    n = len(before)
    motion = np.broadcast_to(np.eye(3), (n, 3, 3)).copy()
    motion[:, 0, 2], motion[:, 1, 2] = -distance * sin, distance * cos
    noise_gain = np.zeros((n, 3, 2))
    noise_gain[:, 0, 0], noise_gain[:, 1, 0] = cos, sin
    noise_gain[:, 0, 1], noise_gain[:, 1, 1] = -distance / 2.0 * sin, distance / 2.0 * cos
    noise_gain[:, 2, 1] = 1.0
    variances = np.column_stack(((sigma_translation * distance) ** 2,
                                 (sigma_rotation * turn) ** 2))
    spread = np.einsum("nij,nj,nkj->nik", noise_gain, variances, noise_gain)
    return np.einsum("nij,njk,nlk->nil", motion, covariance, motion) + spread


class OdometerFrames:
    """Every robot's odometer pose in its ``odom`` frame, and its covariance, step by step.

    ``start`` is the odometer at ``t = 0`` (``(n, 3)``, map coordinates).
    """

    def __init__(self, start: np.ndarray, sigma_translation: np.ndarray,
                 sigma_rotation: np.ndarray) -> None:
        self.start = np.array(start, dtype=np.float64)
        self.sigma_translation = np.asarray(sigma_translation, dtype=np.float64)
        self.sigma_rotation = np.asarray(sigma_rotation, dtype=np.float64)
        n = len(self.start)
        self.pose = np.zeros((n, 3))  # in the odom frames
        self.covariance = np.zeros((n, 3, 3))
        self._noisy = bool(np.any(self.sigma_translation > 0) or np.any(self.sigma_rotation > 0))

    def restart(self) -> None:
        """Back at the start (a run started again by a reset): pose and covariance 0."""
        self.pose = np.zeros_like(self.pose)
        self.covariance = np.zeros_like(self.covariance)

    def update(self, odometer: np.ndarray) -> None:
        """Take the odometer's current poses (map coordinates) as the next step's."""
        pose = relative_poses(self.start, odometer)
        if self._noisy:
            self.covariance = propagate(self.covariance, self.pose, pose,
                                        self.sigma_translation, self.sigma_rotation)
        self.pose = pose
