"""The odometer of a recorded run, rebuilt from its trajectory and seed, as the bridge shows it.

A run folder does not record the odometer, but the engine's odometer is a
function of the true motion and the run's seed: step ``k`` moves each robot
along an arc of length ``d`` turning ``tau`` (``mimics.engine.dynamics``),
and the odometer integrates ``d + n_1 sigma_translation |d|`` and ``tau +
n_2 sigma_rotation |tau|`` with the draws ``(n_1, n_2)`` of robot ``i``'s row
of the ``odometry`` stream's step ``k`` (``mimics.engine.sensors``,
``mimics.engine.noise_streams``). ``d`` and ``tau`` are read back from two
consecutive recorded true poses: ``tau = wrap(theta' - theta)`` and, with the
chord's projection ``c`` on the mid heading ``theta + tau / 2``, ``d = c (tau /
2) / sin(tau / 2)`` (``c`` on a straight step). The measured velocity the
bridge publishes as the odometry's twist is the recorded true one plus the
``velocity`` stream's draws of that step (bit for bit, as the engine adds them).

The rebuilt odometer agrees with the engine's to float rounding, not bit for
bit: the engine's arcs of nearly straight steps (radius ``d / tau`` up to
``1e8`` m) round their positions to ``radius * 2**-52``, and ``d`` read back
carries that rounding (under ``1e-8`` m over a 40 s run of the line scenario;
the odometer's own noise is centimetres per metre).

It needs every step of every robot (``record_every`` 1) and no robot moved by
an edit (a moved robot's odometer restarts at its new pose, which the rows
do not show); :func:`odometer_gap` says why a run cannot be rebuilt.
Pose and covariance in each robot's ``odom`` frame come from the live
bridge's own :class:`~mimics.interfaces.ros.odometry_frame.OdometerFrames`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimics.engine.dynamics import advance_pose
from mimics.engine.noise_streams import StepStreams
from mimics.engine.state import TypeArrays
from mimics.interfaces.ros.odometry_frame import OdometerFrames, wrap
from mimics.interfaces.rosexport.source import Trajectory
from mimics.world.scenario import Scenario

STRAIGHT = 1e-9  # rad: the engine's threshold under which a step is a straight chord


@dataclass(frozen=True)
class OdometerTrack:
    """What the bridge's ``odom`` topics say, one entry per trajectory row (same order)."""

    pose: np.ndarray  # (rows, 3): the odometer in the robot's odom frame
    covariance: np.ndarray  # (rows, 3, 3): of ``pose``


def step_bounds(trajectory: Trajectory) -> list[tuple[int, int, int]]:
    """``(step, first row, end row)`` of each recorded step, in order."""
    starts = np.flatnonzero(np.diff(trajectory.step, prepend=-1) != 0)
    ends = np.append(starts[1:], trajectory.rows)
    return [(int(trajectory.step[s]), int(s), int(e)) for s, e in zip(starts, ends, strict=True)]


def odometer_gap(trajectory: Trajectory, scenario: Scenario, seed: object) -> str | None:
    """Why the odometer of this run cannot be rebuilt, or None when it can."""
    if not isinstance(seed, int) or isinstance(seed, bool):
        return "the run's seed is not recorded in scenario.toml"
    moved = [edit.step for edit in scenario.edits if edit.kind == "move_robot"]
    if moved:
        return f"a robot was moved by an edit at step {moved[0]}"
    last = np.full(scenario.robot_count, -1, dtype=np.int64)
    for step, start, end in step_bounds(trajectory):
        robots = trajectory.robot[start:end]
        if np.any(last[robots] != step - 1):
            return (f"trajectory.parquet skips steps before step {step} (the run was recorded "
                    f"with record_every > 1; the odometer needs every step)")
        last[robots] = step
    if trajectory.rows and np.any(last < 0):
        return "trajectory.parquet lacks robots at step 0"
    return None


def arc_increments(before: np.ndarray, after: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The ``(distance, turn)`` of the arcs taking ``(n, 3)`` poses ``before`` to ``after``."""
    turn = wrap(after[:, 2] - before[:, 2])
    mid = before[:, 2] + 0.5 * turn
    chord = (after[:, 0] - before[:, 0]) * np.cos(mid) + (after[:, 1] - before[:, 1]) * np.sin(mid)
    half = 0.5 * turn
    arc = np.abs(turn) >= STRAIGHT
    ratio = np.ones_like(turn)
    ratio[arc] = half[arc] / np.sin(half[arc])
    return chord * ratio, turn


def odometer_track(trajectory: Trajectory, scenario: Scenario, seed: int) -> OdometerTrack:
    """The odometer of every trajectory row (check :func:`odometer_gap` first)."""
    types = TypeArrays.from_scenario(scenario)
    n = scenario.robot_count
    noisy_odometer = bool({"sigma_translation", "sigma_rotation"} & types.noisy)
    odometry_stream = StepStreams(seed, "odometry")
    true_pose = np.column_stack((trajectory.x, trajectory.y, trajectory.theta))
    pose_out = np.empty((trajectory.rows, 3))
    covariance_out = np.empty((trajectory.rows, 3, 3))
    pose_now = np.zeros((n, 3))  # the last recorded true pose of each robot
    odometer = np.zeros((n, 3))  # map coordinates, as the engine keeps it
    frames: OdometerFrames | None = None
    for step, start, end in step_bounds(trajectory):
        robots = trajectory.robot[start:end]
        rows = true_pose[start:end]
        if frames is None:  # step 0: the odometer starts at the start pose
            pose_now[robots] = odometer[robots] = rows
            frames = OdometerFrames(odometer, types.sigma_translation, types.sigma_rotation)
        else:
            if noisy_odometer:
                distance, turn = arc_increments(pose_now[robots], rows)
                # step k's rows come from the move made at step k - 1, with its draws
                draws = odometry_stream.at(step - 1).standard_normal((n, 2))[robots]
                measured_distance = (distance + draws[:, 0]
                                     * types.sigma_translation[robots] * np.abs(distance))
                measured_turn = turn + draws[:, 1] * types.sigma_rotation[robots] * np.abs(turn)
                odometer[robots] = advance_pose(odometer[robots], measured_distance,
                                                measured_turn)
            else:  # the engine copies the true pose into a noise-free odometer
                odometer[robots] = rows
            pose_now[robots] = rows
            frames.update(odometer)
        pose_out[start:end] = frames.pose[robots]
        covariance_out[start:end] = frames.covariance[robots]
    return OdometerTrack(pose_out, covariance_out)


def measured_velocity(trajectory: Trajectory, scenario: Scenario,
                      seed: object) -> np.ndarray | None:
    """The measured ``(v, w)`` of every trajectory row: the true velocity plus the
    ``velocity`` stream's draws of the row's step (taken after the move, as the engine
    senses); None when the sensor is noisy and the seed unknown."""
    types = TypeArrays.from_scenario(scenario)
    velocity = np.column_stack((trajectory.v, trajectory.w))
    if "sigma_velocity" not in types.noisy:
        return velocity
    if not isinstance(seed, int) or isinstance(seed, bool):
        return None
    stream, n = StepStreams(seed, "velocity"), scenario.robot_count
    for _, start, end in step_bounds(trajectory):
        robots = trajectory.robot[start:end]
        noise = stream.at(int(trajectory.step[start])).standard_normal((n, 2))[robots]
        velocity[start:end] += noise * types.sigma_velocity[robots].reshape(-1, 1)
    return velocity
