"""What each per-step topic carries, free of any ROS library: shared by ROS 1 and ROS 2.

The transports (``odometry``, ``frames`` and ``markers`` here; the ROS 2
bridge) only put these values into their message classes:

* :class:`OdometryReadings`: per robot, the pose, velocity, covariance and
  velocity variances of ``odom`` (the odometer in its ``odom`` frame, see
  :mod:`~mimics.interfaces.ros.odometry_frame`), ``pose`` (the positioning
  sensor in ``map``) and the ground truth (a robot that has stopped: its
  pose, with a zero twist);
* :class:`ScanReadings`: per robot, the ranger's ranges and which beams hit
  something (a stopped robot's last scan);
* :func:`stalled`: Stage's stall flag of each robot (``is_crashed``): the step's;
* :func:`fixed_frames`: the ``/tf_static`` frames of the run's robots;
* :func:`step_markers`: the live markers of a step (footprints, ids, goals),
  built by the export's marker functions with any message factory.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from mimics.engine.state import Status
from mimics.interfaces.ros.names import MAP_FRAME, RosNames
from mimics.interfaces.ros.odometry_frame import OdometerFrames

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation
    from mimics.engine.state import WorldState
    from mimics.interfaces.rosexport.pieces import MessagePieces

NO_COVARIANCE = np.zeros((3, 3))
STILL = np.zeros(2)  # (v, w) of a robot that has stopped


class Reading(NamedTuple):
    """One ``nav_msgs/Odometry``'s values: ``pose`` ``(x, y, theta)``, ``velocity``
    ``(v, w)``, the 3x3 ``covariance`` of the pose and the ``variance`` of v and w."""

    pose: np.ndarray
    velocity: np.ndarray
    covariance: np.ndarray
    variance: tuple[float, float]


class OdometryReadings:
    """Every robot's odometer, measured pose and true pose, step by step."""

    def __init__(self, sim: Simulation) -> None:
        types = sim.types
        # the odometer starts at the start pose (the engine copies the pose into it)
        self.frames = OdometerFrames(sim.state.odometry, types.sigma_translation,
                                     types.sigma_rotation)
        self._velocity_variance = [(float(sigma) ** 2,) * 2 for sigma in types.sigma_velocity]
        self._position_covariance = [np.diag([float(sigma) ** 2] * 2 + [0.0])
                                     for sigma in types.sigma_position]

    def update(self, sim: Simulation) -> None:
        """Take the current step's odometer (step 0: at its start, covariance 0, also
        when a reset starts the run again)."""
        if sim.state.step > 0:
            self.frames.update(sim.state.odometry)
        else:
            self.frames.restart()

    def odom(self, sim: Simulation, robot: int) -> Reading:
        """The odometer's pose in the robot's ``odom`` frame and the measured velocity."""
        return Reading(self.frames.pose[robot], _moving(sim, robot, sim.state.measured_velocity),
                       self.frames.covariance[robot], self._velocity_variance[robot])

    def pose(self, sim: Simulation, robot: int) -> Reading:
        """The positioning sensor's pose in ``map`` and the measured velocity."""
        return Reading(sim.state.measured_pose[robot],
                       _moving(sim, robot, sim.state.measured_velocity),
                       self._position_covariance[robot], self._velocity_variance[robot])

    def truth(self, sim: Simulation, robot: int) -> Reading:
        """The true pose in ``map`` and the true velocity, covariance 0."""
        return Reading(sim.state.pose[robot], _moving(sim, robot, sim.state.velocity),
                       NO_COVARIANCE, (0.0, 0.0))


def _moving(sim: Simulation, robot: int, velocity: np.ndarray) -> np.ndarray:
    """``velocity[robot]``, or 0 for a robot that has stopped: it stands where it stopped
    (its measured velocity would still carry the sensor's noise)."""
    return velocity[robot] if sim.state.status[robot] == Status.ACTIVE else STILL


class ScanReadings:
    """Each robot's ranger reading as published: an active robot's current scan, a stopped
    robot's last (the engine scans active robots only; Stage's stalled robots go on
    scanning, so a held scan misses what moves past afterwards)."""

    def __init__(self, sim: Simulation) -> None:
        self.beam_count = sim.types.beam_count
        n, beams = sim.state.n, int(self.beam_count.max(initial=0))
        self._ranges = np.full((n, beams), np.inf)
        self._hit = np.zeros((n, beams), dtype=bool)

    def scan(self, sim: Simulation, robot: int) -> tuple[np.ndarray, np.ndarray]:
        """``(ranges, hit)`` of the robot's beams: distances, and which hit something."""
        beams = int(self.beam_count[robot])
        state = sim.state
        if state.status[robot] == Status.ACTIVE:
            self._ranges[robot, :beams] = state.scan[robot, :beams]
            self._hit[robot, :beams] = state.scan_hit[robot, :beams] != -2
        return self._ranges[robot, :beams], self._hit[robot, :beams]


def stalled(state: WorldState) -> np.ndarray:
    """Each robot's stall flag (``int8``), as Stage's ``Stalled()``: 1 while its move is
    undone against a wall or a robot (``on_collision = "stall"``, the ``stage`` names'
    default: 0 again once it drives away), or once a collision deactivated it (it stays
    against the obstacle); else 0."""
    return (state.stalled | (state.status == Status.COLLIDED)).astype(np.int8)


def fixed_frames(beam_count: np.ndarray, names: RosNames) -> list[tuple[str, str]]:
    """``(parent, child)`` of every identity frame on ``/tf_static``: ``base_footprint ->
    base_link`` (``stage`` names) and ``base_link -> laser`` for robots with a ranger."""
    fixed = []
    for i in range(len(beam_count)):
        footprint = names.footprint_frame(i)
        if footprint is not None:
            fixed.append((footprint, names.base_frame(i)))
        if beam_count[i] > 0:
            fixed.append((names.base_frame(i), names.laser_frame(i)))
    return fixed


def step_markers(build: MessagePieces, sim: Simulation) -> list[Any]:
    """The current step's markers: per robot its footprint at its true pose in ``map``
    (coloured by status), its index as text, and its goal when it has one."""
    # here, not at the top: the export's modules load only once a viewer subscribes
    from mimics.interfaces.rosexport.markers import footprint_marker, goal_marker, id_marker

    state, scenario = sim.state, sim.scenario
    stamp = round(state.time * 1e9)
    markers = []
    for robot in range(state.n):
        x, y, theta = (float(value) for value in state.pose[robot])
        kind = scenario.robot_type(robot)
        markers.append(footprint_marker(build, stamp, robot, int(state.status[robot]),
                                        kind.length, kind.width, MAP_FRAME, (x, y, theta)))
        markers.append(id_marker(build, stamp, robot, x, y))
        goal = state.goal[robot]
        if np.all(np.isfinite(goal)):
            markers.append(goal_marker(build, stamp, robot, goal))
    return markers
