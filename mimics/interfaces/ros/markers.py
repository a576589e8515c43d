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

import rospy
from visualization_msgs.msg import MarkerArray

from mimics.interfaces.ros.readings import step_markers
from mimics.interfaces.rosexport.pieces import MessagePieces

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
        self._publisher.publish(MarkerArray(markers=step_markers(self._messages, sim)))

    def close(self) -> None:
        """Withdraw the topic."""
        self._publisher.unregister()
