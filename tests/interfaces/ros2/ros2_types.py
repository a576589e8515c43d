"""The test's own ROS 2 message types, written from ROS 2 Humble's definitions (rosidl's
IDL mapping: ``pkg::msg::dds_::Type_``), independently of mimics' ``ros2.messages``."""

# no `from __future__ import annotations`: Cyclone reads the field types at run time
from dataclasses import dataclass, field

from cyclonedds.idl import IdlStruct
from cyclonedds.idl import types as t
from cyclonedds.idl.annotations import final


@final
@dataclass
class Stamp(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: t.int32 = 0
    nanosec: t.uint32 = 0


@final
@dataclass
class StdHeader(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Stamp = field(default_factory=Stamp)
    frame_id: str = ""


@final
@dataclass
class Vec3(IdlStruct, typename="geometry_msgs::msg::dds_::Vector3_"):
    x: t.float64 = 0.0
    y: t.float64 = 0.0
    z: t.float64 = 0.0


@final
@dataclass
class Position(IdlStruct, typename="geometry_msgs::msg::dds_::Point_"):
    x: t.float64 = 0.0
    y: t.float64 = 0.0
    z: t.float64 = 0.0


@final
@dataclass
class Rotation(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    x: t.float64 = 0.0
    y: t.float64 = 0.0
    z: t.float64 = 0.0
    w: t.float64 = 1.0


@final
@dataclass
class PlanarPose(IdlStruct, typename="geometry_msgs::msg::dds_::Pose_"):
    position: Position = field(default_factory=Position)
    orientation: Rotation = field(default_factory=Rotation)


@final
@dataclass
class PoseCov(IdlStruct, typename="geometry_msgs::msg::dds_::PoseWithCovariance_"):
    pose: PlanarPose = field(default_factory=PlanarPose)
    covariance: t.array[t.float64, 36] = field(default_factory=lambda: [0.0] * 36)


@final
@dataclass
class Velocity(IdlStruct, typename="geometry_msgs::msg::dds_::Twist_"):
    linear: Vec3 = field(default_factory=Vec3)
    angular: Vec3 = field(default_factory=Vec3)


@final
@dataclass
class VelocityCov(IdlStruct, typename="geometry_msgs::msg::dds_::TwistWithCovariance_"):
    twist: Velocity = field(default_factory=Velocity)
    covariance: t.array[t.float64, 36] = field(default_factory=lambda: [0.0] * 36)


@final
@dataclass
class Odom(IdlStruct, typename="nav_msgs::msg::dds_::Odometry_"):
    header: StdHeader = field(default_factory=StdHeader)
    child_frame_id: str = ""
    pose: PoseCov = field(default_factory=PoseCov)
    twist: VelocityCov = field(default_factory=VelocityCov)


@final
@dataclass
class Goal(IdlStruct, typename="geometry_msgs::msg::dds_::PoseStamped_"):
    header: StdHeader = field(default_factory=StdHeader)
    pose: PlanarPose = field(default_factory=PlanarPose)


@final
@dataclass
class Scan(IdlStruct, typename="sensor_msgs::msg::dds_::LaserScan_"):
    header: StdHeader = field(default_factory=StdHeader)
    angle_min: t.float32 = 0.0
    angle_max: t.float32 = 0.0
    angle_increment: t.float32 = 0.0
    time_increment: t.float32 = 0.0
    scan_time: t.float32 = 0.0
    range_min: t.float32 = 0.0
    range_max: t.float32 = 0.0
    ranges: t.sequence[t.float32] = field(default_factory=list)
    intensities: t.sequence[t.float32] = field(default_factory=list)


@final
@dataclass
class SimClock(IdlStruct, typename="rosgraph_msgs::msg::dds_::Clock_"):
    clock: Stamp = field(default_factory=Stamp)


# std_srvs/srv/Trigger as rmw_cyclonedds_cpp frames it: its request header first
@final
@dataclass
class TriggerCall(IdlStruct, typename="std_srvs::srv::dds_::Trigger_Request_"):
    guid: t.uint64 = 0
    seq: t.int64 = 0
    structure_needs_at_least_one_member: t.uint8 = 0


@final
@dataclass
class TriggerAnswer(IdlStruct, typename="std_srvs::srv::dds_::Trigger_Response_"):
    guid: t.uint64 = 0
    seq: t.int64 = 0
    success: bool = False
    message: str = ""


# tf2_msgs/TFMessage (with geometry_msgs/Transform and TransformStamped) and std_msgs/Int8
@final
@dataclass
class Placement(IdlStruct, typename="geometry_msgs::msg::dds_::Transform_"):
    translation: Vec3 = field(default_factory=Vec3)
    rotation: Rotation = field(default_factory=Rotation)


@final
@dataclass
class StampedPlacement(IdlStruct, typename="geometry_msgs::msg::dds_::TransformStamped_"):
    header: StdHeader = field(default_factory=StdHeader)
    child_frame_id: str = ""
    transform: Placement = field(default_factory=Placement)


@final
@dataclass
class Frames(IdlStruct, typename="tf2_msgs::msg::dds_::TFMessage_"):
    transforms: t.sequence[StampedPlacement] = field(default_factory=list)


@final
@dataclass
class Flag(IdlStruct, typename="std_msgs::msg::dds_::Int8_"):
    data: t.int8 = 0
