"""visualization_msgs/MarkerArray: the robots' footprints, goals and ids.

One set of marker builders serves the export (``/markers`` in a bag or MCAP,
built with ``rosbags`` types) and the live bridge (``/mimics/markers``,
:mod:`mimics.interfaces.ros.markers`, built with ``rospy``'s classes): each
builder takes a message factory (:class:`~.pieces.MessagePieces`) and
needs no ROS library itself.

- A footprint (namespace ``footprint``, id = robot index) is a flat box
  (CUBE) of the robot type's length along x and width along y, coloured by
  status: active blue, reached goal green, collided red, escaped grey,
  deadlock orange, error purple. The export draws it in the robot's own
  frame ``base_link`` (``robot_i/base_link``; the viewer moves it with ``/tf``); the live
  bridge in ``map`` at the robot's pose.
- A goal (namespace ``goal``) is a thin cylinder of 0.2 m diameter at the
  goal in frame ``map``, in the active colour; robots without a goal have none.
- An id (namespace ``id``, live only) is the robot's index as text
  (TEXT_VIEW_FACING) above its footprint.

In an export: at time 0, every footprint and goal; afterwards, at each step
where robots change status, their footprints again in the new colour (a
marker with the same namespace and id replaces the old one).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.state import Status
from mimics.interfaces.rosexport.pieces import MessagePieces, Stamped
from mimics.interfaces.rosexport.topics import MAP_FRAME, MARKER_ARRAY, MARKERS_TOPIC
from mimics.world.scenario import Scenario

if TYPE_CHECKING:
    from mimics.interfaces.ros.names import RosNames
    from mimics.interfaces.rosexport.source import Trajectory

FOOTPRINT_HEIGHT = 0.1  # m: a flat box, drawn on the floor
GOAL_DIAMETER = 0.2  # m
LABEL_HEIGHT = 0.3  # m: the text's height, drawn above the footprint
COLOURS = {
    Status.ACTIVE: (0.12, 0.47, 0.71, 0.8), Status.REACHED_GOAL: (0.17, 0.63, 0.17, 0.8),
    Status.COLLIDED: (0.84, 0.15, 0.16, 0.8), Status.ESCAPED: (0.5, 0.5, 0.5, 0.8),
    Status.DEADLOCK: (1.0, 0.5, 0.05, 0.8), Status.ERROR: (0.58, 0.4, 0.74, 0.8),
    Status.REMOVED: (0.85, 0.85, 0.85, 0.8),
}
LABEL_COLOUR = (1.0, 1.0, 1.0, 1.0)
CUBE, CYLINDER, TEXT_VIEW_FACING = 1, 3, 9  # visualization_msgs/Marker types


def marker_messages(messages: MessagePieces, trajectory: Trajectory, scenario: Scenario,
                    names: RosNames) -> Iterator[Stamped]:
    """Footprints (in each robot's ``base_link`` of ``names``) and goals at time 0, then the
    footprints whose status changed."""
    last = np.full(scenario.robot_count, -1, dtype=np.int64)
    starts = np.flatnonzero(np.diff(trajectory.step, prepend=-1) != 0)
    ends = np.append(starts[1:], trajectory.rows)
    for start, end in zip(starts, ends, strict=True):
        stamp = int(trajectory.stamp[start])
        markers = []
        for k in range(start, end):
            robot, status = int(trajectory.robot[k]), int(trajectory.status[k])
            if status != last[robot]:
                kind = scenario.robot_type(robot)
                markers.append(footprint_marker(messages, stamp, robot, status, kind.length,
                                                kind.width, names.base_frame(robot)))
                last[robot] = status
        if start == 0:
            markers += [goal_marker(messages, stamp, robot, goal) for robot, goal
                        in enumerate(scenario.goals) if not np.isnan(goal[0])]
        if markers:
            yield Stamped(stamp, MARKERS_TOPIC, messages.make(MARKER_ARRAY, markers=markers))


def footprint_marker(messages: MessagePieces, stamp: int, robot: int, status: int,
                     length: float, width: float, frame: str,
                     pose: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> Any:
    """Robot ``robot``'s footprint at ``pose`` (x, y, heading) in ``frame``."""
    scale = messages.make("geometry_msgs/msg/Vector3", x=float(length), y=float(width),
                          z=FOOTPRINT_HEIGHT)
    return messages.make("visualization_msgs/msg/Marker",
                         header=messages.header(stamp, frame), ns="footprint",
                         id=robot, type=CUBE, action=0,
                         pose=messages.pose(*pose, z=FOOTPRINT_HEIGHT / 2), scale=scale,
                         color=messages.color(COLOURS[Status(status)]),
                         frame_locked=frame != MAP_FRAME)


def goal_marker(messages: MessagePieces, stamp: int, robot: int, goal: np.ndarray) -> Any:
    """Robot ``robot``'s goal, in ``map``."""
    scale = messages.make("geometry_msgs/msg/Vector3", x=GOAL_DIAMETER, y=GOAL_DIAMETER, z=0.02)
    return messages.make("visualization_msgs/msg/Marker",
                         header=messages.header(stamp, MAP_FRAME), ns="goal", id=robot,
                         type=CYLINDER, action=0,
                         pose=messages.pose(goal[0], goal[1], 0.0), scale=scale,
                         color=messages.color(COLOURS[Status.ACTIVE]))


def id_marker(messages: MessagePieces, stamp: int, robot: int, x: float, y: float) -> Any:
    """Robot ``robot``'s index as text above its position (``x``, ``y``) in ``map``."""
    scale = messages.make("geometry_msgs/msg/Vector3", x=0.0, y=0.0, z=LABEL_HEIGHT)
    return messages.make("visualization_msgs/msg/Marker",
                         header=messages.header(stamp, MAP_FRAME), ns="id", id=robot,
                         type=TEXT_VIEW_FACING, action=0,
                         pose=messages.pose(x, y, 0.0, z=FOOTPRINT_HEIGHT + LABEL_HEIGHT),
                         scale=scale, color=messages.color(LABEL_COLOUR), text=str(robot))
