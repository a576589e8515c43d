"""The small pieces every ROS message uses, for any message factory; no ROS library needed.

:class:`MessagePieces` builds headers, points, poses, transforms and colours
from two methods a factory supplies: ``make(msgtype, **fields)`` and
``stamp(nanoseconds)``. The export's factory
(:class:`~mimics.interfaces.rosexport.conversion.Messages`, ``rosbags``
types) and the live bridge's (:class:`~mimics.interfaces.ros.markers.RospyMessages`,
``rospy``'s classes) share them, so the message builders written against
them (the markers of :mod:`~mimics.interfaces.rosexport.markers`) serve both.

Also here: the export's time base. Exported stamps are
:data:`EXPORT_EPOCH_NS` plus the simulated time: ROS reads a zero time as
"unset" (``rospy.Time.now()`` before the first ``/clock``; ``Time(0)`` in a
tf lookup means "the latest"; C++ rosbag refuses to write a message before
``ros::TIME_MIN``, 1 ns; MCAP writers have taken a log time of 0 for "none",
foxglove/mcap#502), so a run starting at 0 makes its first step ambiguous.

>>> nanoseconds(0.3) - EXPORT_EPOCH_NS
300000000
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from typing import Any, NamedTuple

import numpy as np

#: 2000-01-01T00:00:00Z in nanoseconds since the Unix epoch: simulated time 0 of an
#: export (Foxglove and rqt_bag show the run on 1 January 2000, from midnight UTC).
EXPORT_EPOCH_NS = 946_684_800 * 1_000_000_000


class MessagePieces(ABC):
    """Headers, points, poses, transforms and colours built with ``make`` and ``stamp``."""

    @abstractmethod
    def make(self, msgtype: str, **fields: Any) -> Any:
        """A message of ``msgtype`` (``"geometry_msgs/msg/Point"``) with ``fields``."""

    @abstractmethod
    def stamp(self, nanoseconds: int) -> Any:
        """A time message from whole nanoseconds."""

    def header(self, nanoseconds: int, frame_id: str) -> Any:
        """A ``std_msgs/Header`` stamped ``nanoseconds`` in frame ``frame_id``."""
        return self.make("std_msgs/msg/Header", stamp=self.stamp(nanoseconds), frame_id=frame_id)

    def point(self, x: float, y: float, z: float = 0.0) -> Any:
        """A ``geometry_msgs/Point``."""
        return self.make("geometry_msgs/msg/Point", x=float(x), y=float(y), z=float(z))

    def quaternion(self, yaw: float) -> Any:
        """The ``geometry_msgs/Quaternion`` of a rotation by ``yaw`` about z."""
        half = 0.5 * float(yaw)
        return self.make("geometry_msgs/msg/Quaternion", x=0.0, y=0.0, z=math.sin(half),
                         w=math.cos(half))

    def pose(self, x: float, y: float, yaw: float, z: float = 0.0) -> Any:
        """A planar ``geometry_msgs/Pose`` (at height ``z``)."""
        return self.make("geometry_msgs/msg/Pose", position=self.point(x, y, z),
                         orientation=self.quaternion(yaw))

    def transform(self, nanoseconds: int, parent: str, child: str, x: float, y: float,
                  yaw: float) -> Any:
        """A ``geometry_msgs/TransformStamped`` placing ``child`` in ``parent``."""
        translation = self.make("geometry_msgs/msg/Vector3", x=float(x), y=float(y), z=0.0)
        return self.make("geometry_msgs/msg/TransformStamped",
                         header=self.header(nanoseconds, parent), child_frame_id=child,
                         transform=self.make("geometry_msgs/msg/Transform",
                                             translation=translation,
                                             rotation=self.quaternion(yaw)))

    def color(self, rgba: tuple[float, float, float, float]) -> Any:
        """A ``std_msgs/ColorRGBA``."""
        r, g, b, a = rgba
        return self.make("std_msgs/msg/ColorRGBA", r=r, g=g, b=b, a=a)


class Stamped(NamedTuple):
    """A message ready to write: its log time (ns, the same as its stamp) and topic."""

    time: int
    topic: str
    message: Any


def nanoseconds(time: float) -> int:
    """Simulated seconds as an export's stamp: whole nanoseconds from :data:`EXPORT_EPOCH_NS`."""
    return EXPORT_EPOCH_NS + round(float(time) * 1e9)


def stamps(times: np.ndarray) -> np.ndarray:
    """:func:`nanoseconds` of many times at once (int64; rounds as it does, half to even)."""
    return EXPORT_EPOCH_NS + np.rint(np.asarray(times, dtype=np.float64) * 1e9).astype(np.int64)
