"""`mimics export`: MCAP and ROS 1 bag files read back by independent readers equal the run.

Readers: rosbags' own (``AnyReader``, for both files), Foxglove's ``mcap`` +
``mcap-ros2-support`` (decodes the MCAP from the ros2msg schemas it carries, as
Foxglove does), and ROS 1's ``rosbag`` (the Debian package, run by the system's
Python) for the bag.
"""

from __future__ import annotations

import json
import math
import subprocess
from collections import Counter, defaultdict
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap_ros2.decoder import DecoderFactory
from rosbags.highlevel import AnyReader

from mimics.algorithms import go_to_goal
from mimics.engine.simulation import Simulation
from mimics.interfaces.cli import main
from mimics.interfaces.rosexport import export_run
from mimics.records.run_folder import load_run
from mimics.records.runner import run_to_folder
from mimics.scenarios.line import scenario as line
from mimics.world.maps import Map
from mimics.world.robot_types import SWARMBOT
from mimics.world.scenario import Scenario, Settings
from tests.records.helpers import ScanCapture
from tests.system_packages import require

# stamps start at 2000-01-01T00:00:00Z (docs/how-to/ros-export.md), not at the Unix epoch
EPOCH = int(datetime(2000, 1, 1, tzinfo=UTC).timestamp()) * 1_000_000_000

ROBOTS = 3


@pytest.fixture(scope="module")
def exported(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """A 1.5 s run of the line scenario (3 robots, scans recorded) exported both ways."""
    folder = tmp_path_factory.mktemp("rosexport")
    capture = ScanCapture()
    sim = Simulation(line(robots=ROBOTS, random_yaw=False), go_to_goal, seed=2, time_limit=1.5,
                     observers=[capture])
    run_to_folder(sim, folder / "run", record_scans=True, robot_logs="off")
    code = main(["export", str(folder / "run"), "--mcap", str(folder / "run.mcap"),
                 "--bag", str(folder / "run.bag")])
    assert code == 0
    return {"folder": folder, "run": load_run(folder / "run"), "capture": capture.seen}


def read_rosbags(path: Path) -> dict[str, list[tuple[int, Any]]]:
    """Every message by topic, as (log time, message), with rosbags' reader."""
    found: dict[str, list[tuple[int, Any]]] = defaultdict(list)
    with AnyReader([path]) as reader:
        for connection, time, raw in reader.messages():
            found[connection.topic].append((time, reader.deserialize(raw, connection.msgtype)))
    return found


def stamp_ns(stamp: Any) -> int:
    return int(stamp.sec) * 1_000_000_000 + int(stamp.nanosec)


def yaw(q: Any) -> float:
    return 2 * math.atan2(q.z, q.w)


def angle_gap(a: float, b: float) -> float:
    return abs(math.remainder(a - b, 2 * math.pi))


@pytest.mark.parametrize("name", ["run.mcap", "run.bag"])
def test_messages_equal_the_runs_parquet_data(exported: dict[str, Any], name: str) -> None:
    run = exported["run"]
    topics = read_rosbags(exported["folder"] / name)
    trajectory = run.trajectory.sort_values(["step", "robot"], kind="stable")
    steps = sorted(trajectory["step"].unique())
    assert len(topics["/tf"]) == len(steps) and len(topics["/map"]) == 1
    assert len(topics["/tf_static"]) == 1 and len(topics["/markers"]) >= 1
    for robot in range(ROBOTS):
        rows = trajectory[trajectory["robot"] == robot]
        odom = topics[f"/robot_{robot}/ground_truth"]
        assert len(odom) == len(rows)
        for (time, message), row in zip(odom, rows.itertuples(), strict=True):
            assert time == stamp_ns(message.header.stamp) == EPOCH + round(row.time * 1e9)
            assert message.header.frame_id == "map"
            assert message.child_frame_id == f"robot_{robot}/base_link"
            position = message.pose.pose.position
            assert (position.x, position.y) == (row.x, row.y)
            assert angle_gap(yaw(message.pose.pose.orientation), row.theta) < 1e-12
            assert (message.twist.twist.linear.x, message.twist.twist.angular.z) == (row.v, row.w)
    for (time, message), step in zip(topics["/tf"], steps, strict=True):
        rows = trajectory[trajectory["step"] == step]
        assert time == EPOCH + round(rows["time"].iloc[0] * 1e9)
        # the live bridge's tree: map -> robot_r/odom -> robot_r/base_link, per robot
        pairs = [(t.header.frame_id, t.child_frame_id) for t in message.transforms]
        assert pairs == [pair for r in rows["robot"] for pair in (
            ("map", f"robot_{r}/odom"), (f"robot_{r}/odom", f"robot_{r}/base_link"))]
        for k, row in enumerate(rows.itertuples()):
            to_odom, to_body = (t.transform for t in message.transforms[2 * k:2 * k + 2])
            # composed by hand: the body at the positioning sensor's pose (here the true one)
            a, b = yaw(to_odom.rotation), yaw(to_body.rotation)
            x = to_odom.translation.x + math.cos(a) * to_body.translation.x - math.sin(
                a) * to_body.translation.y
            y = to_odom.translation.y + math.sin(a) * to_body.translation.x + math.cos(
                a) * to_body.translation.y
            assert abs(x - row.x) < 1e-9 and abs(y - row.y) < 1e-9
            assert angle_gap(a + b, row.theta) < 1e-9


@pytest.mark.parametrize("name", ["run.mcap", "run.bag"])
def test_scans_equal_the_engines_within_the_quantum(exported: dict[str, Any], name: str) -> None:
    run, seen = exported["run"], exported["capture"]
    topics = read_rosbags(exported["folder"] / name)
    quantum = run.scans.quantum
    offsets = np.array(line(robots=1).types[0].ranger.beam_offsets())
    total = 0
    for robot in range(ROBOTS):
        recorded = run.scans.robot(robot)
        messages = topics[f"/robot_{robot}/scan"]
        assert [t for t, _ in messages] == [EPOCH + round(t * 1e9) for t in recorded.times]
        for (_, message), step in zip(messages, recorded.steps, strict=True):
            engine, owner = seen[(int(step), robot)]
            ranges = np.asarray(message.ranges, dtype=np.float64)
            hit = owner != -2
            assert np.array_equal(np.isinf(ranges), ~hit)  # REP 117: nothing in range is +inf
            # float32 rounding adds at most 2**-24 of the range (8 m: under 1 micron)
            assert np.max(np.abs(ranges[hit] - engine[hit])) <= quantum / 2 + 1e-6
            assert message.header.frame_id == f"robot_{robot}/laser"
            assert math.isclose(message.angle_min, offsets[0], rel_tol=1e-7)
            assert math.isclose(message.angle_max, offsets[-1], rel_tol=1e-7)
            assert math.isclose(message.range_max, 30.0)
            total += 1
    assert total == len(seen)  # every scan the engine made (every step recorded)


def test_mcap_opens_in_foxgloves_reader(exported: dict[str, Any]) -> None:
    run = exported["run"]
    counts: Counter[str] = Counter()
    with (exported["folder"] / "run.mcap").open("rb") as stream:
        reader = make_reader(stream, decoder_factories=[DecoderFactory()])
        assert reader.get_header().profile == "ros2"
        schemas = {s.name: s.encoding for s in reader.get_summary().schemas.values()}
        assert schemas == dict.fromkeys(
            ["nav_msgs/msg/OccupancyGrid", "tf2_msgs/msg/TFMessage", "nav_msgs/msg/Odometry",
             "sensor_msgs/msg/LaserScan", "visualization_msgs/msg/MarkerArray"], "ros2msg")
        first_odom = None
        for _, channel, message, decoded in reader.iter_decoded_messages(log_time_order=True):
            counts[channel.topic] += 1
            if channel.topic == "/robot_1/ground_truth" and first_odom is None:
                first_odom = (message.log_time, decoded.pose.pose.position.y)
    assert counts["/robot_1/ground_truth"] == len(run.robot(1))
    assert counts["/robot_2/scan"] == len(run.scans.robot(2).steps)
    assert first_odom == (EPOCH, float(run.robot(1)["y"].iloc[0]))


def test_markers_show_footprints_and_goals(exported: dict[str, Any]) -> None:
    topics = read_rosbags(exported["folder"] / "run.mcap")
    time, first = topics["/markers"][0]
    assert time == EPOCH
    footprints = [m for m in first.markers if m.ns == "footprint"]
    goals = [m for m in first.markers if m.ns == "goal"]
    kind = line(robots=1).types[0]
    assert [m.header.frame_id for m in footprints] == [f"robot_{i}/base_link"
                                                       for i in range(ROBOTS)]
    assert all((m.scale.x, m.scale.y) == (kind.length, kind.width) for m in footprints)
    goal_positions = [(m.pose.position.x, m.pose.position.y) for m in goals]
    assert goal_positions == [tuple(g) for g in line(robots=ROBOTS).goals.tolist()]


def test_ros1_rosbag_reads_the_bag(exported: dict[str, Any]) -> None:
    """ROS 1's own reader (python3-rosbag, outside the venv) agrees with the run."""
    require("rosbag")
    script = ("import json, sys, rosbag, collections\n"
              "bag = rosbag.Bag(sys.argv[1])\n"
              "counts = collections.Counter(); first = {}\n"
              "for topic, msg, t in bag.read_messages():\n"
              "    counts[topic] += 1\n"
              "    if topic == '/robot_0/ground_truth' and 't' not in first:\n"
              "        first.update(t=t.to_nsec(), stamp=msg.header.stamp.to_nsec(),\n"
              "                     x=msg.pose.pose.position.x)\n"
              "    if topic == '/map': first['map'] = [msg.info.width, msg.info.height]\n"
              "print(json.dumps({'counts': counts, 'first': first}))\n")
    done = subprocess.run(["/usr/bin/python3", "-c", script, str(exported["folder"] / "run.bag")],
                          capture_output=True, text=True, check=True, timeout=60)
    found = json.loads(done.stdout)
    run = exported["run"]
    assert found["counts"]["/robot_0/ground_truth"] == len(run.robot(0))
    assert found["counts"]["/robot_2/scan"] == len(run.scans.robot(2).steps)
    assert found["counts"]["/tf"] == run.trajectory["step"].nunique()
    assert found["first"]["t"] == found["first"]["stamp"] == EPOCH
    assert found["first"]["x"] == run.robot(0)["x"].iloc[0]
    # the grid covers the map's bounds at the default 0.05 m
    bounds = run.scenario.map.bounds
    assert found["first"]["map"] == [round((bounds[2] - bounds[0]) / 0.05),
                                     round((bounds[3] - bounds[1]) / 0.05)]


def test_occupancy_grid_of_a_hand_made_map(tmp_path: Path) -> None:
    """A 2 x 1 m map at 0.5 m: a 4 x 2 grid; occupied cells worked out by hand."""
    walls = [(0.25, 0.25, 1.75, 0.25),  # along row 0, columns 0 to 3
             (1.2, 0.6, 1.3, 0.9),  # inside cell (row 1, column 2)
             (0.1, 0.9, 0.4, 0.6)]  # inside cell (row 1, column 0)
    world = Scenario.from_matrix([[0.75, 0.75, 0.0, 0.0]], Map(walls, (0.0, 0.0, 2.0, 1.0)),
                                 SWARMBOT, settings=Settings(dt=0.1, time_limit=0.2))
    run_to_folder(Simulation(world, go_to_goal, seed=1), tmp_path / "run", robot_logs="off")
    export_run(tmp_path / "run", mcap=tmp_path / "m.mcap", bag=tmp_path / "m.bag",
               resolution=0.5)
    for name in ("m.mcap", "m.bag"):
        (_, grid), = read_rosbags(tmp_path / name)["/map"]
        assert (grid.info.width, grid.info.height, grid.info.resolution) == (4, 2, 0.5)
        assert (grid.info.origin.position.x, grid.info.origin.position.y) == (0.0, 0.0)
        cells = np.asarray(grid.data).reshape(2, 4)  # row 0 is the bottom (y from 0 to 0.5)
        assert cells.tolist() == [[100, 100, 100, 100], [100, 0, 100, 0]]
        assert "/robot_0/scan" not in read_rosbags(tmp_path / name)  # no scans recorded
