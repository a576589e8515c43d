"""Building and serialising ROS messages, in one place, for ROS 1 and ROS 2 alike.

The message modules say only the fields that carry meaning
(``messages.make("nav_msgs/msg/Odometry", header=..., pose=...)``); every
other field gets its type's zero value here, so the same code builds the
ROS 2 (Humble) and the ROS 1 (Noetic) definitions, which differ in fields
(``seq`` in a ROS 1 header, the textures of a ROS 2 marker). Types come from
the ``rosbags`` package's type stores; ROS 1's lacks ``tf2_msgs/TFMessage``,
which is registered here from its one-line definition.

>>> ros2 = Messages(2)
>>> stamp = ros2.stamp(1_500_000_000)
>>> stamp.sec, stamp.nanosec
(1, 500000000)
>>> header = ros2.header(1_500_000_000, "map")
>>> ros2.make("std_msgs/msg/Header", stamp=stamp, frame_id="map") == header
True
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from rosbags.interfaces import Nodetype
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from mimics.interfaces.rosexport.pieces import MessagePieces, Stamped, nanoseconds, stamps

__all__ = ["Messages", "Stamped", "nanoseconds", "stamps", "yaw_of"]

TF_MESSAGE = "tf2_msgs/msg/TFMessage"
_ROS1_TF_DEFINITION = "geometry_msgs/TransformStamped[] transforms"

# NumPy dtypes of the ROS primitive types that rosbags keeps as arrays
_ARRAY_DTYPES = {"bool": np.bool_, "int8": np.int8, "uint8": np.uint8, "byte": np.uint8,
                 "char": np.uint8, "int16": np.int16, "uint16": np.uint16, "int32": np.int32,
                 "uint32": np.uint32, "int64": np.int64, "uint64": np.uint64,
                 "float32": np.float32, "float64": np.float64}


class Messages(MessagePieces):
    """ROS message construction and serialisation for one ROS version.

    Args:
        ros_version: 2 (MCAP, CDR encoding, Humble types) or 1 (bag, ROS 1 encoding).
    """

    def __init__(self, ros_version: int) -> None:
        self.ros_version = ros_version
        self._defaults: dict[str, tuple[tuple[str, Any], ...]] = {}
        if ros_version == 2:
            self.store = get_typestore(Stores.ROS2_HUMBLE)
        else:
            self.store = get_typestore(Stores.ROS1_NOETIC)
            if TF_MESSAGE not in self.store.types:
                self.store.register(get_types_from_msg(_ROS1_TF_DEFINITION, TF_MESSAGE))

    def make(self, msgtype: str, **fields: Any) -> Any:
        """A message of ``msgtype`` with ``fields``; the fields not given are zero/empty."""
        defaults = self._defaults.get(msgtype)
        if defaults is None:
            defaults = self._defaults[msgtype] = tuple(
                (name, self._zero(kind, detail))
                for name, (kind, detail) in self.store.fielddefs[msgtype][1])
        values = [fields.pop(name, zero) for name, zero in defaults]
        if fields:
            raise TypeError(f"{msgtype} has no field {', '.join(fields)}")
        return self.store.types[msgtype](*values)

    def _zero(self, kind: int, detail: Any) -> Any:
        """A field's zero value; shared by every message made (none is ever changed)."""
        if kind == Nodetype.BASE:
            base = detail[0]
            return "" if base == "string" else (False if base == "bool" else 0)
        if kind == Nodetype.NAME:
            return self.make(detail)
        element_kind, element = detail[0]
        length = detail[1] if kind == Nodetype.ARRAY else 0
        if element_kind == Nodetype.BASE and element[0] in _ARRAY_DTYPES:
            zeros = np.zeros(length, dtype=_ARRAY_DTYPES[element[0]])
            zeros.flags.writeable = False
            return zeros
        return [self._zero(element_kind, element) for _ in range(length)]

    def serialize(self, message: Any) -> bytes | memoryview:
        """The message's bytes in this version's wire format (CDR or ROS 1)."""
        if self.ros_version == 2:
            return self.store.serialize_cdr(message, message.__msgtype__)
        return self.store.serialize_ros1(message, message.__msgtype__)

    def stamp(self, nanoseconds: int) -> Any:
        """A time (ROS 2 ``builtin_interfaces/Time``, ROS 1 ``time``) from nanoseconds."""
        seconds, rest = divmod(int(nanoseconds), 1_000_000_000)
        return self.store.types["builtin_interfaces/msg/Time"](sec=seconds, nanosec=rest)


def yaw_of(quaternion: Any) -> float:
    """The yaw (rotation about z) of a planar quaternion message."""
    return 2.0 * math.atan2(quaternion.z, quaternion.w)
