"""A live ``mimics ros2`` run seen from outside: names, types, wire format and values.

One lockstep run of ``line`` (2 robots, 1.5 s) observed over loopback by
:mod:`tests.interfaces.ros2.observer` (the test's own ROS 2 types); its
samples are checked against ROS 2's conventions, against ``rosbags``' ROS 2
Humble type store (an independent CDR decoder), and against the run's own
records.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from mimics.records.run_folder import load_run
from tests.interfaces.ros2.loopback import next_domain
from tests.interfaces.ros2.observer import STAGE_NAMES, TWISTS, Observed, observe_run
from tests.interfaces.ros2.ros2_types import Clock, LaserScan, Odometry

ROBOTS, DT, SECONDS = 2, 0.1, 1.5


@pytest.fixture(scope="module")
def observed(tmp_path_factory: pytest.TempPathFactory) -> Observed:
    folder = tmp_path_factory.mktemp("ros2") / "run"
    seen = observe_run(folder, next_domain(), ROBOTS,
                       ["--time", str(SECONDS), "--record-scans", "--strict-lockstep",
                        "--startup-grace", "1", "--timeout", "20"])
    assert seen.returncode == 0, seen.stderr
    return seen


def _stamp(header: object) -> float:
    return header.stamp.sec + header.stamp.nanosec * 1e-9  # type: ignore[attr-defined]


def test_topics_and_types_are_ros2s(observed: Observed) -> None:
    expected = {("rt/clock", "rosgraph_msgs::msg::dds_::Clock_"),
                ("rt/tf", "tf2_msgs::msg::dds_::TFMessage_"),
                ("rt/tf_static", "tf2_msgs::msg::dds_::TFMessage_"),
                ("rt/map", "nav_msgs::msg::dds_::OccupancyGrid_"),
                ("rt/mimics/markers", "visualization_msgs::msg::dds_::MarkerArray_")}
    for i in range(ROBOTS):
        expected |= {(f"rt/robot_{i}/odom", "nav_msgs::msg::dds_::Odometry_"),
                     (f"rt/robot_{i}/ground_truth", "nav_msgs::msg::dds_::Odometry_"),
                     (f"rt/robot_{i}/scan", "sensor_msgs::msg::dds_::LaserScan_"),
                     (f"rt/robot_{i}/goal", "geometry_msgs::msg::dds_::PoseStamped_")}
    assert expected <= observed.publications


def test_every_sample_is_plain_little_endian_cdr(observed: Observed) -> None:
    samples = [raw for topic in observed.raw.values() for raw in topic]
    assert samples
    assert {raw[:4] for raw in samples} == {b"\x00\x01\x00\x00"}  # CDR_LE, options 0


def test_clock_advances_step_by_step(observed: Observed) -> None:
    clock = [_stamp_of(Clock.deserialize(raw).clock) for raw in observed.raw["rt/clock"]]
    steps = round(SECONDS / DT)
    assert clock == pytest.approx([k * DT for k in range(steps + 1)], abs=1e-9)


def _stamp_of(time: object) -> float:
    return time.sec + time.nanosec * 1e-9  # type: ignore[attr-defined]


def test_ground_truth_and_odometry_match_the_records(observed: Observed) -> None:
    trajectory = load_run(observed.folder).trajectory
    for i in range(ROBOTS):
        truths = [Odometry.deserialize(raw) for raw in observed.raw[f"rt/robot_{i}/ground_truth"]]
        rows = trajectory[trajectory.robot == i].set_index("step")
        assert len(truths) == len(rows)
        for truth in truths:
            row = rows.loc[round(_stamp(truth.header) / DT)]
            q = truth.pose.pose.orientation
            yaw = 2.0 * math.atan2(q.z, q.w)
            assert (truth.header.frame_id, truth.child_frame_id) == ("map",
                                                                     f"robot_{i}/base_link")
            assert truth.pose.pose.position.x == row.x and truth.pose.pose.position.y == row.y
            assert math.remainder(yaw - row.theta, math.tau) == pytest.approx(0.0, abs=1e-12)
            assert truth.twist.twist.linear.x == row.v and truth.twist.twist.angular.z == row.w
        odometry = [Odometry.deserialize(raw) for raw in observed.raw[f"rt/robot_{i}/odom"]]
        first = odometry[0]
        assert _stamp(first.header) == 0.0 and first.header.frame_id == f"robot_{i}/odom"
        assert (first.pose.pose.position.x, first.pose.pose.position.y) == (0.0, 0.0)
        # the commands the observer sent became the references the robot followed
        assert rows.v_ref.iloc[1:].to_numpy() == pytest.approx(TWISTS[i][0])


def test_scans_match_the_recorded_scans(observed: Observed) -> None:
    scans = load_run(observed.folder).scans
    for i in range(ROBOTS):
        recorded = scans.robot(i)
        seen = [LaserScan.deserialize(raw) for raw in observed.raw[f"rt/robot_{i}/scan"]]
        assert [round(_stamp(scan.header) / DT) for scan in seen] == recorded.steps.tolist()
        for scan, ranges, hits in zip(seen, recorded.ranges, recorded.hits, strict=True):
            live = np.array(scan.ranges)
            assert scan.header.frame_id == f"robot_{i}/laser"
            assert np.all(np.isinf(live[~hits]))  # REP 117: no return reads +inf
            assert live[hits] == pytest.approx(ranges[hits], abs=scans.quantum / 2 + 1e-5)
            assert scan.angle_min == pytest.approx(recorded.angles[0], abs=1e-6)
            assert scan.range_max == pytest.approx(recorded.max_range, abs=1e-5)


def test_rosbags_ros2_typestore_reads_every_field(observed: Observed) -> None:
    """An independent CDR decoder (rosbags' ROS 2 Humble definitions) reads the raw samples
    into the values mimics recorded: the layout is ROS 2's, field by field."""
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    trajectory = load_run(observed.folder).trajectory
    rows = trajectory[trajectory.robot == 0].set_index("step")
    for raw in observed.raw["rt/robot_0/ground_truth"]:
        message = store.deserialize_cdr(raw, "nav_msgs/msg/Odometry")
        row = rows.loc[round((message.header.stamp.sec
                              + message.header.stamp.nanosec * 1e-9) / DT)]
        assert message.header.frame_id == "map"
        assert message.child_frame_id == "robot_0/base_link"
        assert (message.pose.pose.position.x, message.pose.pose.position.y) == (row.x, row.y)
        assert message.pose.pose.position.z == 0.0
        assert len(message.pose.covariance) == 36 and not message.pose.covariance.any()
        assert message.twist.twist.linear.x == row.v
        assert message.twist.twist.angular.z == row.w
    scans = load_run(observed.folder).scans.robot(0)
    for raw, ranges, hits in zip(observed.raw["rt/robot_0/scan"], scans.ranges, scans.hits,
                                 strict=True):
        message = store.deserialize_cdr(raw, "sensor_msgs/msg/LaserScan")
        assert message.header.frame_id == "robot_0/laser"
        assert message.ranges.dtype == np.float32 and len(message.ranges) == len(ranges)
        assert message.ranges[hits] == pytest.approx(ranges[hits], abs=0.01)
        assert message.scan_time == pytest.approx(DT)
        assert len(message.intensities) == 0
    clocks = [store.deserialize_cdr(raw, "rosgraph_msgs/msg/Clock").clock
              for raw in observed.raw["rt/clock"]]
    assert [(c.sec, c.nanosec) for c in clocks[:12]] == [(k // 10, (k % 10) * 100_000_000)
                                                         for k in range(12)]


def test_bad_input_is_one_line_and_status_2(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, "-m", "mimics", "ros2", "line", "--names", "ros"],
                          capture_output=True, text=True, check=False, cwd=tmp_path)
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        "mimics: error: --names: expected one of mimics, stage, got 'ros'"]


def test_stage_names_for_a_single_robot(tmp_path: Path) -> None:
    """``--names stage``: stage_ros' topics without a prefix, its frames, and beams that
    hit nothing reading ``range_max``, as stage_ros publishes them."""
    seen = observe_run(tmp_path / "run", next_domain(), 1,
                       ["--names", "stage", "--lockstep", "--strict-lockstep", "--time", "0.5",
                        "--record-scans", "--startup-grace", "0.5", "--timeout", "20"],
                       names=STAGE_NAMES)
    assert seen.returncode == 0, seen.stderr
    assert {("rt/odom", "nav_msgs::msg::dds_::Odometry_"),
            ("rt/base_pose_ground_truth", "nav_msgs::msg::dds_::Odometry_"),
            ("rt/base_scan", "sensor_msgs::msg::dds_::LaserScan_"),
            ("rt/goal", "geometry_msgs::msg::dds_::PoseStamped_")} <= seen.publications
    assert not any(topic.startswith("rt/robot_") for topic, _ in seen.publications)
    odometry = [Odometry.deserialize(raw) for raw in seen.raw["rt/odom"]]
    assert len(odometry) == 6
    assert {(o.header.frame_id, o.child_frame_id) for o in odometry} == {("odom",
                                                                          "base_footprint")}
    recorded = load_run(seen.folder).scans.robot(0)
    for raw, hits in zip(seen.raw["rt/base_scan"], recorded.hits, strict=True):
        scan = LaserScan.deserialize(raw)
        assert scan.header.frame_id == "base_laser_link"
        assert np.array(scan.ranges)[~hits].tolist() == [scan.range_max] * int((~hits).sum())
