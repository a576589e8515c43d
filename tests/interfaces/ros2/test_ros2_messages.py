"""mimics' ROS 2 messages against rosbags' ROS 2 Humble definitions, without a network:
names, layouts and values; ``ROS_DOMAIN_ID``; and the stage names on a live run."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from rosbags.typesys import Stores, get_typestore

from mimics.interfaces.ros.occupancy import Grid
from mimics.interfaces.ros.readings import Reading
from mimics.interfaces.ros2 import conversion as convert
from mimics.interfaces.ros2 import messages as msg
from mimics.interfaces.ros2.transport import domain_id, service_topics
from mimics.world.errors import MimicsError
from tests.interfaces.ros2 import ros2_types as tt

STORE = get_typestore(Stores.ROS2_HUMBLE)


def _decode(message: object, name: str) -> object:
    raw = message.serialize(use_version_2=False)  # type: ignore[attr-defined]
    assert raw[:4] == b"\x00\x01\x00\x00"
    return STORE.deserialize_cdr(raw, name)


@pytest.mark.parametrize("name", sorted(msg.BY_NAME))
def test_every_type_is_rosidls_dds_type_with_rosbags_fields(name: str) -> None:
    kind = msg.BY_NAME[name]
    package, _, short = name.split("/")
    assert kind.__idl_typename__.replace(".", "::") == f"{package}::msg::dds_::{short}_"
    fields = [field for field, _ in STORE.fielddefs[name][1]]
    assert list(kind.__dataclass_fields__) == fields
    _decode(kind(), name)  # the empty message: rosbags reads every field of the layout


def test_odometry_values_and_covariance_cells() -> None:
    covariance = np.array([[1.0, 2.0, 3.0], [4.0, 5.0, 6.0], [7.0, 8.0, 9.0]])
    reading = Reading(np.array([1.5, -2.0, math.pi / 3]), np.array([0.4, -0.1]), covariance,
                      (0.01, 0.02))
    odometry = _decode(convert.odometry(12.3, "robot_1/odom", "robot_1/base_link", reading),
                       "nav_msgs/msg/Odometry")
    assert (odometry.header.stamp.sec, odometry.header.stamp.nanosec) == (12, 300_000_000)
    assert odometry.header.frame_id == "robot_1/odom"
    orientation = odometry.pose.pose.orientation
    assert (orientation.z, orientation.w) == pytest.approx((0.5, math.sqrt(3) / 2))
    cells = odometry.pose.covariance.reshape(6, 6)
    assert cells[np.ix_([0, 1, 5], [0, 1, 5])].tolist() == covariance.tolist()
    assert cells[2:5].sum() == 0 and cells[:, 2:5].sum() == 0
    assert (odometry.twist.twist.linear.x, odometry.twist.twist.angular.z) == (0.4, -0.1)
    assert (odometry.twist.covariance[0], odometry.twist.covariance[35]) == (0.01, 0.02)


def test_grid_transforms_and_markers() -> None:
    cells = np.zeros((2, 3), dtype=np.int8)
    cells[1, 2] = 100
    grid = _decode(convert.grid(Grid(cells, 0.5, (-1.0, 2.0)), 0.0),
                   "nav_msgs/msg/OccupancyGrid")
    assert (grid.info.width, grid.info.height, grid.info.resolution) == (3, 2, 0.5)
    assert grid.data.tolist() == [0, 0, 0, 0, 0, 100]  # row 0 first, as ROS
    assert (grid.info.origin.position.x, grid.info.origin.position.y) == (-1.0, 2.0)
    frames = convert.odometry_transforms(1.0, "robot_0/odom", "robot_0/base_link",
                                         np.array([2.0, 1.0, math.pi / 2]),
                                         np.array([1.0, 0.0, 0.0]))
    tf = _decode(msg.TFMessage(frames), "tf2_msgs/msg/TFMessage")
    # map -> odom: the odometer's (1, 0, 0) must land on the measured (2, 1, pi/2)
    to_odom = tf.transforms[0].transform
    assert (to_odom.translation.x, to_odom.translation.y) == pytest.approx((2.0, 0.0))
    assert tf.transforms[1].child_frame_id == "robot_0/base_link"
    build = convert.IdlMessages()
    marker = build.make("visualization_msgs/msg/Marker", header=build.header(5, "map"),
                        ns="id", id=3, type=9, text="3", color=build.color((1, 0, 0, 1)))
    decoded = _decode(msg.MarkerArray([marker]), "visualization_msgs/msg/MarkerArray")
    assert (decoded.markers[0].ns, decoded.markers[0].id, decoded.markers[0].text) == (
        "id", 3, "3")
    assert decoded.markers[0].header.stamp.nanosec == 5


def test_services_are_framed_with_rmw_cyclonedds_request_header() -> None:
    assert service_topics("/mimics/pause") == ("rq/mimics/pauseRequest",
                                               "rr/mimics/pauseReply")
    raw = msg.TriggerResponse(7, 9, True, "ok").serialize(use_version_2=False)
    # header {uint64 guid; int64 seq}, then Trigger's response (rosbags reads it after it)
    assert int.from_bytes(raw[4:12], "little") == 7 and int.from_bytes(raw[12:20], "little") == 9
    from rosbags.typesys import get_types_from_msg

    store = get_typestore(Stores.ROS2_HUMBLE)  # rosbags' stores have no services: Trigger's
    store.register(get_types_from_msg("bool success\nstring message",  # response, from
                                      "std_srvs/msg/TriggerResponse"))  # std_srvs/Trigger.srv
    body = store.deserialize_cdr(raw[:4] + raw[20:], "std_srvs/msg/TriggerResponse")
    assert (body.success, body.message) == (True, "ok")


def _plain(value: object) -> object:
    """Values as plain Python, to compare Cyclone's messages with rosbags': messages as
    dicts (without rosbags' ``__msgtype__``), arrays as lists, NaN as ``"nan"``."""
    if dataclasses.is_dataclass(value):
        return {item.name: _plain(getattr(value, item.name))
                for item in dataclasses.fields(value) if not item.name.startswith("__")}
    if isinstance(value, list | np.ndarray):
        return [_plain(item) for item in value]
    if isinstance(value, float | np.floating) and math.isnan(value):
        return "nan"
    return value.item() if isinstance(value, np.generic) else value


def _tests_own_samples() -> list[tuple[str, object]]:
    """Samples of the tests' generated types, every float32 value float32-exact."""
    header = tt.Header(tt.Time(12, 345_678_901), "robot_0/base_scan")
    scan = tt.LaserScan(header, -1.5, 1.5, 0.75, 1 / 1024, 0.125, 0.0625, 8.0,
                        [0.5, math.inf, math.nan, 7.25, -0.0], [1.0, 0.0, 2.0, 3.0, 4.0])
    odometry = tt.Odometry(
        tt.Header(tt.Time(-1, 999_999_999), "robot_0/odom"), "robot_0/base_link",
        tt.PoseWithCovariance(tt.Pose(tt.Point(1 / 3, -2 / 7, 1e-300),
                                      tt.Quaternion(0.0, 0.0, math.sin(0.4), math.cos(0.4))),
                              [i / 9 for i in range(36)]),
        tt.TwistWithCovariance(tt.Twist(tt.Vector3(0.3, math.e, math.nan),
                                        tt.Vector3(0.0, 0.0, -math.pi / 5)),
                               [-i / 11 for i in range(36)]))
    tf = tt.TFMessage([tt.TransformStamped(tt.Header(frame_id="map"), f"robot_{i}/odom",
                                           tt.Transform(tt.Vector3(1.5, -0.25 * i),
                                                        tt.Quaternion(z=0.6, w=0.8)))
                       for i in range(3)])
    return [("sensor_msgs/msg/LaserScan", scan), ("nav_msgs/msg/Odometry", odometry),
            ("tf2_msgs/msg/TFMessage", tf)]


@pytest.mark.parametrize(("name", "sample"), [pytest.param(name, sample, id=name)
                                              for name, sample in _tests_own_samples()])
def test_the_tests_generated_types_are_what_rosbags_reads(name: str, sample: object) -> None:
    """The tests' own types (``ros2_types``, generated from rosbags' field definitions)
    serialise, as Cyclone writes them (XCDR1, little-endian), into what rosbags' own
    decoder reads back value for value: sequences, arrays, nested messages, inf and NaN."""
    package, _, short = name.split("/")
    assert type(sample).__idl_typename__ == f"{package}::msg::dds_::{short}_"
    assert type(sample).__idl_annotations__["extensibility"] == "final"
    assert sample.serialize() == sample.serialize(use_version_2=False)  # type: ignore[attr-defined]
    assert _plain(_decode(sample, name)) == _plain(sample)


def test_the_tests_generated_types_keep_ros2_defaults() -> None:
    """rosbags' definitions carry no default values; ROS 2's .msg files set
    Quaternion's ``w`` to 1 (the identity rotation), the rest zero or empty."""
    assert _plain(tt.Pose()) == {"position": {"x": 0.0, "y": 0.0, "z": 0.0},
                                 "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0}}
    assert tt.PoseWithCovariance().covariance == [0.0] * 36
    assert (tt.LaserScan().ranges, tt.Header().frame_id, tt.Int8().data) == ([], "", 0)
    assert tt.TriggerCall(7, 9).serialize()[4:] == bytes([7, *[0] * 7, 9, *[0] * 7, 0])


@pytest.mark.parametrize(("value", "domain"), [(None, 0), ("", 0), ("7", 7), ("232", 232)])
def test_ros_domain_id(value: str | None, domain: int) -> None:
    assert domain_id({} if value is None else {"ROS_DOMAIN_ID": value}) == domain


@pytest.mark.parametrize("value", ["233", "-1", "one", "1.5"])
def test_a_bad_ros_domain_id_is_named(value: str) -> None:
    with pytest.raises(MimicsError, match=r"^ROS_DOMAIN_ID: expected a whole number from 0 "
                                          r"to 232, got"):
        domain_id({"ROS_DOMAIN_ID": value})


def test_commands_written_by_rosbags_are_read() -> None:
    """The subscriptions' direction: ROS 2 messages encoded by rosbags (an independent
    encoder) decode into the commands they mean."""
    types = STORE.types
    vector = types["geometry_msgs/msg/Vector3"]
    twist = types["geometry_msgs/msg/Twist"](vector(0.5, 0.0, 0.0), vector(0.0, 0.0, -0.25))
    raw = STORE.serialize_cdr(twist, "geometry_msgs/msg/Twist")
    command = convert.command_from_twist(msg.Twist.deserialize(bytes(raw)))
    assert (command.kind, command.first, command.second) == ("twist", 0.5, -0.25)
    layout = types["std_msgs/msg/MultiArrayLayout"](
        [types["std_msgs/msg/MultiArrayDimension"]("x", 3, 3)], 0)
    array = types["std_msgs/msg/Float64MultiArray"](layout, np.array([0.3, 1.2, 4.2]))
    raw = STORE.serialize_cdr(array, "std_msgs/msg/Float64MultiArray")
    command = convert.command_from_array(msg.Float64MultiArray.deserialize(bytes(raw)), 0.1)
    assert (command.kind, command.first, command.second, command.step) == (
        "reference", 0.3, 1.2, 42)
    with pytest.raises(ValueError, match=r"cmd_vel: linear\.x and angular\.z must be finite"):
        convert.command_from_twist(msg.Twist(msg.Vector3(math.nan, 0.0, 0.0)))
