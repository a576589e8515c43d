"""visualization_msgs/MarkerArray: the robots' footprints and goals.

On ``/markers``: at time 0, every robot's footprint (namespace
``footprint``, id = robot index) and goal (namespace ``goal``); afterwards, at
each step where robots change status, their footprints again in the new
colour (a marker with the same namespace and id replaces the old one).

- A footprint is a flat box (CUBE) of the robot type's length along x and
  width along y, in the robot's own frame ``robot_i/base_link`` (so the
  viewer moves it with ``/tf``), coloured by status: active blue, reached
  goal green, collided red, escaped grey, deadlock orange, error purple.
- A goal is a thin cylinder of 0.2 m diameter at the goal in frame ``map``,
  in the robot's active colour; robots without a goal have none.
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np

from mimics.engine.state import Status
from mimics.interfaces.rosexport.conversion import Messages, Stamped
from mimics.interfaces.rosexport.source import Trajectory
from mimics.interfaces.rosexport.topics import MAP_FRAME, MARKER_ARRAY, MARKERS_TOPIC, base_link
from mimics.world.scenario import Scenario

FOOTPRINT_HEIGHT = 0.1  # m: a flat box, drawn on the floor
GOAL_DIAMETER = 0.2  # m
COLOURS = {
    Status.ACTIVE: (0.12, 0.47, 0.71, 0.8), Status.REACHED_GOAL: (0.17, 0.63, 0.17, 0.8),
    Status.COLLIDED: (0.84, 0.15, 0.16, 0.8), Status.ESCAPED: (0.5, 0.5, 0.5, 0.8),
    Status.DEADLOCK: (1.0, 0.5, 0.05, 0.8), Status.ERROR: (0.58, 0.4, 0.74, 0.8),
    Status.REMOVED: (0.85, 0.85, 0.85, 0.8),
}
CUBE, CYLINDER = 1, 3  # visualization_msgs/Marker types


def marker_messages(messages: Messages, trajectory: Trajectory,
                    scenario: Scenario) -> Iterator[Stamped]:
    """Footprints and goals at time 0, then the footprints whose status changed."""
    last = np.full(scenario.robot_count, -1, dtype=np.int64)
    starts = np.flatnonzero(np.diff(trajectory.step, prepend=-1) != 0)
    ends = np.append(starts[1:], trajectory.rows)
    for start, end in zip(starts, ends, strict=True):
        stamp = int(trajectory.stamp[start])
        markers = []
        for k in range(start, end):
            robot, status = int(trajectory.robot[k]), int(trajectory.status[k])
            if status != last[robot]:
                markers.append(_footprint(messages, stamp, scenario, robot, status))
                last[robot] = status
        if start == 0:
            markers += [_goal(messages, stamp, robot, goal) for robot, goal
                        in enumerate(scenario.goals) if not np.isnan(goal[0])]
        if markers:
            yield Stamped(stamp, MARKERS_TOPIC, messages.make(MARKER_ARRAY, markers=markers))


def _footprint(messages: Messages, stamp: int, scenario: Scenario, robot: int,
               status: int) -> Any:
    kind = scenario.robot_type(robot)
    scale = messages.make("geometry_msgs/msg/Vector3", x=float(kind.length), y=float(kind.width),
                          z=FOOTPRINT_HEIGHT)
    pose = messages.make("geometry_msgs/msg/Pose",
                         position=messages.point(0, 0, FOOTPRINT_HEIGHT / 2),
                         orientation=messages.quaternion(0.0))
    return messages.make("visualization_msgs/msg/Marker",
                         header=messages.header(stamp, base_link(robot)), ns="footprint",
                         id=robot, type=CUBE, action=0, pose=pose, scale=scale,
                         color=messages.color(COLOURS[Status(status)]), frame_locked=True)


def _goal(messages: Messages, stamp: int, robot: int, goal: np.ndarray) -> Any:
    scale = messages.make("geometry_msgs/msg/Vector3", x=GOAL_DIAMETER, y=GOAL_DIAMETER, z=0.02)
    return messages.make("visualization_msgs/msg/Marker",
                         header=messages.header(stamp, MAP_FRAME), ns="goal", id=robot,
                         type=CYLINDER, action=0,
                         pose=messages.pose(goal[0], goal[1], 0.0), scale=scale,
                         color=messages.color(COLOURS[Status.ACTIVE]))
