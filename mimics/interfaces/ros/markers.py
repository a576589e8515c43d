"""``/mimics/markers``: live ``visualization_msgs/MarkerArray`` of footprints, goals and ids.

Published with every step's observations (lockstep and realtime alike),
stamped with simulated time, while something subscribes (else not even
built: three markers per robot and step would cost a 100-robot lockstep
run). Per robot: its footprint at its true pose in ``map``, coloured by
status (namespace ``footprint``), its index as text above it (``id``) and
its goal (``goal``, robots with a goal only); a marker's id is its robot's
index. The markers are those of the export, built by the same functions
(:mod:`mimics.interfaces.rosexport.markers`) with ``rospy``'s message
classes (:class:`RospyMessages`).
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

import numpy as np
import rospy
from visualization_msgs.msg import MarkerArray

from mimics.interfaces.rosexport.markers import footprint_marker, goal_marker, id_marker
from mimics.interfaces.rosexport.pieces import MessagePieces
from mimics.interfaces.rosexport.topics import MAP_FRAME

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation

MARKERS_TOPIC = "/mimics/markers"


class RospyMessages(MessagePieces):
    """The marker builders' message factory with ``rospy``'s generated classes."""

    def __init__(self) -> None:
        self._classes: dict[str, type] = {}

    def make(self, msgtype: str, **fields: Any) -> Any:
        """``make("geometry_msgs/msg/Point", x=1.0)`` gives ``geometry_msgs.msg.Point(x=1.0)``."""
        kind = self._classes.get(msgtype)
        if kind is None:
            package, _, name = msgtype.split("/")
            kind = self._classes[msgtype] = getattr(importlib.import_module(f"{package}.msg"),
                                                    name)
        return kind(**fields)

    def stamp(self, nanoseconds: int) -> rospy.Time:
        """A ``rospy.Time`` of whole nanoseconds."""
        return rospy.Time(nsecs=int(nanoseconds))


class MarkerPublisher:
    """Publishes every robot's markers in one MarkerArray per step."""

    def __init__(self) -> None:
        self._messages = RospyMessages()
        self._publisher = rospy.Publisher(MARKERS_TOPIC, MarkerArray, queue_size=2)

    def publish(self, sim: Simulation) -> None:
        """The markers of the current step (built only when something subscribes)."""
        if self._publisher.get_num_connections() == 0:
            return
        state, scenario, build = sim.state, sim.scenario, self._messages
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
        self._publisher.publish(MarkerArray(markers=markers))

    def close(self) -> None:
        """Withdraw the topic."""
        self._publisher.unregister()
