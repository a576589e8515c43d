"""The tests' ROS 2 Humble message types for Cyclone DDS, generated from rosbags' typestore.

rosbags' ``Stores.ROS2_HUMBLE`` (an independent source: neither mimics' ``ros2.messages``
nor typed by hand) gives each message's fields, kinds and order; each becomes the DDS type
rosidl generates for it (``pkg/msg/T`` is ``pkg::msg::dds_::T_``), final, as ROS 2's
middlewares send it (XCDR1). The one hand-written part is rmw_cyclonedds_cpp's service
framing: its request header ``{guid, seq}`` before the request or the response.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from typing import Any

from cyclonedds.idl import IdlStruct, make_idl_struct
from cyclonedds.idl import types as t
from cyclonedds.idl.annotations import final
from rosbags.interfaces import Nodetype
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

STORE = get_typestore(Stores.ROS2_HUMBLE)

# rosidl's IDL type of each ROS 2 base type (ROS 2's char is an unsigned byte)
_BASE: dict[str, Any] = {
    "bool": bool, "byte": t.byte, "char": t.uint8, "int8": t.int8, "uint8": t.uint8,
    "int16": t.int16, "uint16": t.uint16, "int32": t.int32, "uint32": t.uint32,
    "int64": t.int64, "uint64": t.uint64, "float32": t.float32, "float64": t.float64,
}
# the constants the .msg files set that rosbags' field definitions leave out
# (geometry_msgs/msg/Quaternion.msg: ``float64 w 1``, the identity rotation)
_ROS_DEFAULTS: dict[str, dict[str, object]] = {"geometry_msgs/msg/Quaternion": {"w": 1.0}}
_GENERATED: dict[str, type[IdlStruct]] = {}

FieldDesc = tuple[Any, Any]  # rosbags' (Nodetype, details) of one field


def _element(desc: FieldDesc) -> tuple[Any, Callable[[], object]]:
    """A base or named field's Cyclone type and a maker of its ROS 2 default value."""
    kind, details = desc
    if kind == Nodetype.NAME:
        message = generate(details)
        return message, message
    name, bound = details
    if name == "string":
        return (t.bounded_str[bound] if bound else str), str
    if name not in _BASE:
        raise ValueError(f"{name}: a ROS 2 base type these tests do not map to Cyclone DDS")
    return _BASE[name], (float if name.startswith("float") else bool if name == "bool" else int)


def _field(desc: FieldDesc) -> tuple[Any, Any]:
    """A field's Cyclone type and its dataclass default (zero, empty, or a default message)."""
    kind, details = desc
    if kind in (Nodetype.BASE, Nodetype.NAME):
        idl_type, make = _element(desc)
        return idl_type, dataclasses.field(default_factory=make)
    (element, make), size = _element(details[0]), details[1]
    if kind == Nodetype.ARRAY:
        return t.array[element, size], dataclasses.field(
            default_factory=lambda: [make() for _ in range(size)])
    return (t.sequence[element, size] if size else t.sequence[element]), dataclasses.field(
        default_factory=list)


def _struct(ros_name: str, fielddefs: list[tuple[str, FieldDesc]],
            header: dict[str, Any] | None = None) -> type[IdlStruct]:
    """The final Cyclone type rosidl names ``pkg::kind::dds_::T_`` for ``pkg/kind/T``,
    with ``header``'s fields (zero by default) before the message's."""
    package, kind, short = ros_name.split("/")
    types = dict(header or {})
    defaults = {name: dataclasses.field(default=0) for name in types}
    for name, desc in fielddefs:
        types[name], defaults[name] = _field(desc)
    for name, value in _ROS_DEFAULTS.get(ros_name, {}).items():
        defaults[name] = dataclasses.field(default=value)
    made = make_idl_struct(short, f"{package}::{kind}::dds_::{short}_", types,
                           dataclassify=False)
    for name, default in defaults.items():
        setattr(made, name, default)  # read by dataclass() as the field's default
    return final(dataclasses.dataclass(made))


def generate(ros_name: str) -> type[IdlStruct]:
    """ROS 2 Humble's ``ros_name`` (``pkg/msg/T``) as a Cyclone type, made once."""
    if ros_name not in _GENERATED:
        _GENERATED[ros_name] = _struct(ros_name, STORE.fielddefs[ros_name][1])
    return _GENERATED[ros_name]


Time = generate("builtin_interfaces/msg/Time")
Header = generate("std_msgs/msg/Header")
Int8 = generate("std_msgs/msg/Int8")
Vector3 = generate("geometry_msgs/msg/Vector3")
Point = generate("geometry_msgs/msg/Point")
Quaternion = generate("geometry_msgs/msg/Quaternion")
Pose = generate("geometry_msgs/msg/Pose")
PoseWithCovariance = generate("geometry_msgs/msg/PoseWithCovariance")
PoseStamped = generate("geometry_msgs/msg/PoseStamped")
Twist = generate("geometry_msgs/msg/Twist")
TwistWithCovariance = generate("geometry_msgs/msg/TwistWithCovariance")
Transform = generate("geometry_msgs/msg/Transform")
TransformStamped = generate("geometry_msgs/msg/TransformStamped")
Odometry = generate("nav_msgs/msg/Odometry")
LaserScan = generate("sensor_msgs/msg/LaserScan")
TFMessage = generate("tf2_msgs/msg/TFMessage")
Clock = generate("rosgraph_msgs/msg/Clock")

# std_srvs/srv/Trigger ("---\nbool success\nstring message") as rmw_cyclonedds_cpp frames
# it: its request header, then the request (empty, so rosidl's placeholder byte, as in
# std_msgs/msg/Empty) or the response
REQUEST_HEADER: dict[str, Any] = {"guid": t.uint64, "seq": t.int64}
TriggerCall = _struct("std_srvs/srv/Trigger_Request", STORE.fielddefs["std_msgs/msg/Empty"][1],
                      REQUEST_HEADER)
TriggerAnswer = _struct(
    "std_srvs/srv/Trigger_Response",
    get_types_from_msg("bool success\nstring message", "std_srvs/msg/Trigger_Response")[
        "std_srvs/msg/Trigger_Response"][1], REQUEST_HEADER)
