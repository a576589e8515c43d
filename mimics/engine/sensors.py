"""Noisy sensors: positioning, odometry and communication (the ranger's noise: ranging/).

Every draw comes from the sensor's own stream of the run's seed, step by step
and row by row by robot index (:mod:`mimics.engine.noise_streams`), so the same
seed gives the same noise whatever the algorithm, whatever it reads.
"""

from __future__ import annotations

import numpy as np

from mimics.engine.dynamics import advance_pose
from mimics.engine.noise_streams import StepStreams
from mimics.engine.state import TypeArrays, WorldState

COMMS_COLUMNS = ("id", "x", "y", "theta", "v", "w")


def _noisy(rng: np.random.Generator, values: np.ndarray, sigma: np.ndarray) -> np.ndarray:
    """``values`` plus zero-mean Gaussian noise of per-robot ``sigma`` (rows); ``rng`` is
    the step's stretch of the sensor's stream (a row per robot, whatever its sigma)."""
    noise = rng.standard_normal(values.shape)
    scale = sigma.reshape(-1, *([1] * (values.ndim - 1)))
    return values + noise * scale


def measure_positioning(state: WorldState, types: TypeArrays,
                        streams: dict[str, StepStreams]) -> None:
    """Fill the measured pose, velocity and acceleration from the ground truth, with the
    noise of this step (``streams``: ``"position"``, ``"velocity"``, ``"acceleration"``)."""
    noise, step = types.noisy, state.step
    # Without noise the measured values are plain copies: skip the temporaries.
    if "sigma_position" in noise:
        state.measured_pose[:, :2] = _noisy(streams["position"].at(step), state.pose[:, :2],
                                            types.sigma_position)
        state.measured_pose[:, 2] = state.pose[:, 2]
    else:  # the whole pose in one copy
        state.measured_pose[:] = state.pose
    if "sigma_velocity" in noise:
        state.measured_velocity[:] = _noisy(streams["velocity"].at(step), state.velocity,
                                            types.sigma_velocity)
    else:
        state.measured_velocity[:] = state.velocity
    if "sigma_acceleration" in noise:
        state.measured_acceleration[:] = _noisy(streams["acceleration"].at(step),
                                                state.acceleration, types.sigma_acceleration)
    else:
        state.measured_acceleration[:] = state.acceleration


def odometry_is_exact(state: WorldState, types: TypeArrays) -> bool:
    """Whether the odometer has no noise and still reads the true pose, bit for bit.

    Then integrating the next step's increments gives the new true pose
    exactly (``update_odometry`` runs the same ``advance_pose`` on the same
    numbers), so the engine may copy the pose instead. Without odometry noise
    this holds for the whole run: both start from the initial stage.
    """
    if "sigma_translation" in types.noisy or "sigma_rotation" in types.noisy:
        return False
    return state.odometry.tobytes() == state.pose.tobytes()


def update_odometry(state: WorldState, types: TypeArrays, distance: np.ndarray,
                    turn: np.ndarray, moving: np.ndarray | None, streams: StepStreams) -> None:
    """Integrate noisy increments into the odometer; noise only where there is motion.

    ``moving`` is a mask of the robots that moved, or None when all did; ``streams`` is
    the odometry's stream: step k draws a row ``[translation, rotation]`` per robot,
    whichever of the two is noisy.
    """
    draws = streams.at(state.step).standard_normal((state.n, 2))
    measured_distance = distance + draws[:, 0] * types.sigma_translation * np.abs(distance)
    measured_turn = turn + draws[:, 1] * types.sigma_rotation * np.abs(turn)
    updated = advance_pose(state.odometry, measured_distance, measured_turn)
    if moving is None:
        state.odometry[:] = updated
    else:
        state.odometry[moving] = updated[moving]


def comms_matrix(state: WorldState) -> np.ndarray:
    """All active robots' measured ``[id, x, y, theta, v, w]`` rows (see ``COMMS_COLUMNS``)."""
    active = np.flatnonzero(state.active)
    table = np.empty((len(active), len(COMMS_COLUMNS)))
    table[:, 0] = active
    table[:, 1:4] = state.measured_pose[active]
    table[:, 4:6] = state.measured_velocity[active]
    return table


def within_range(table: np.ndarray, x: float, y: float, comm_range: float) -> np.ndarray:
    """Rows of a comms table within ``comm_range`` of ``(x, y)``."""
    if not np.isfinite(comm_range):
        return table
    near = np.hypot(table[:, 1] - x, table[:, 2] - y) <= comm_range
    return table[near]
