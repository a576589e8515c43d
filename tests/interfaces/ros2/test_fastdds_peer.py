"""The Fast DDS peer against Cyclone DDS, and against ``mimics ros2``, on loopback only.

The Cyclone DDS side of the first two tests is written here from ROS 2's conventions
alone (topic ``/a/b`` is ``rt/a/b``, type ``pkg/msg/T`` is ``pkg::msg::dds_::T_``, the
field layouts of ROS 2 Humble from rosbags' typestore, XCDR1: ``ros2_types``), not from
mimics' code: a fake simulator that steps two unicycles in lockstep with the peer's
Twists. The peer is built from ``peer/`` with Debian's Fast DDS (see ``fastdds_peer``), so
neither side shares code with mimics.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import time
import tomllib
from collections.abc import Iterator
from dataclasses import dataclass, field, fields, is_dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest
from cyclonedds.core import Policy, Qos
from cyclonedds.domain import Domain, DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from tests.interfaces.ros2.fastdds_peer import (
    CYCLONE_LOOPBACK,
    answered,
    build_peer,
    final_poses,
    finish_peer,
    next_domain,
    peer_environment,
    start_peer,
    stop_peer,
)
from tests.interfaces.ros2.ros2_types import (
    Clock,
    Header,
    LaserScan,
    Odometry,
    Point,
    Pose,
    PoseStamped,
    PoseWithCovariance,
    Quaternion,
    TFMessage,
    Time,
    Transform,
    TransformStamped,
    Twist,
    TwistWithCovariance,
    Vector3,
)

XCDR1 = Policy.DataRepresentation(use_cdrv0_representation=True)  # what ROS 2 sends
RELIABLE = Qos(Policy.Reliability.Reliable(duration(seconds=1)), Policy.Durability.Volatile,
               Policy.History.KeepLast(10), XCDR1)
BEST_EFFORT = Qos(Policy.Reliability.BestEffort, Policy.Durability.Volatile,
                  Policy.History.KeepLast(10), XCDR1)
LATCHED = Qos(Policy.Reliability.Reliable(duration(seconds=1)),
              Policy.Durability.TransientLocal, Policy.History.KeepLast(1), XCDR1)
GOAL_TOLERANCE, MAX_LINEAR, MAX_ANGULAR = 0.1, 0.5, 1.5
DT = 0.1  # s per lockstep step


def quaternion(yaw: float) -> Quaternion:
    return Quaternion(0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))


def stamp(t: float) -> Time:
    return Time(int(t), round((t - int(t)) * 1e9))


@dataclass
class Unicycle:
    """A robot of the fake simulator: its true pose in ``map``, its start and its goal."""

    x: float
    y: float
    yaw: float
    goal: tuple[float, float]
    start: tuple[float, float, float] = field(init=False)

    def __post_init__(self) -> None:
        self.start = (self.x, self.y, self.yaw)

    def in_odom(self) -> tuple[float, float, float]:
        """The pose relative to the start pose: what the odometry frame reports."""
        sx, sy, syaw = self.start
        dx, dy = self.x - sx, self.y - sy
        return (math.cos(syaw) * dx + math.sin(syaw) * dy,
                -math.sin(syaw) * dx + math.cos(syaw) * dy, self.yaw - syaw)

    def move(self, linear: float, angular: float) -> None:
        self.x += linear * math.cos(self.yaw) * DT
        self.y += linear * math.sin(self.yaw) * DT
        self.yaw += angular * DT


def expected_command(robot: Unicycle) -> tuple[float, float]:
    """The contract's go-to-goal law, from the true pose in ``map``."""
    remaining = math.hypot(robot.goal[0] - robot.x, robot.goal[1] - robot.y)
    if remaining < GOAL_TOLERANCE:
        return 0.0, 0.0
    error = math.remainder(math.atan2(robot.goal[1] - robot.y, robot.goal[0] - robot.x)
                           - robot.yaw, math.tau)
    return (min(0.8 * remaining, MAX_LINEAR) * max(0.0, math.cos(error)),
            max(-MAX_ANGULAR, min(MAX_ANGULAR, 2.0 * error)))


class FakeSimulator:
    """Publishes what a ROS 2 simulator does, per robot ``i`` and step, and reads Twists."""

    def __init__(self, participant: DomainParticipant, robots: list[Unicycle]) -> None:
        def writer(name: str, kind: type, qos: Qos) -> DataWriter:
            return DataWriter(participant, Topic(participant, name, kind), qos=qos)

        self.robots = robots
        self.clock = writer("rt/clock", Clock, RELIABLE)
        self.tf = writer("rt/tf", TFMessage, RELIABLE)
        self.odom = [writer(f"rt/robot_{i}/odom", Odometry, RELIABLE) for i in range(len(robots))]
        self.scan = [writer(f"rt/robot_{i}/scan", LaserScan, BEST_EFFORT)
                     for i in range(len(robots))]
        self.goal = [writer(f"rt/robot_{i}/goal", PoseStamped, LATCHED)
                     for i in range(len(robots))]
        self.cmd_vel = [DataReader(participant, Topic(participant, f"rt/robot_{i}/cmd_vel", Twist),
                                   qos=RELIABLE) for i in range(len(robots))]
        for i, robot in enumerate(robots):
            self.goal[i].write(PoseStamped(Header(frame_id="map"), Pose(Point(*robot.goal))))

    def wait_for_peer(self, peer: subprocess.Popen[str]) -> None:
        """Until every writer and reader has matched the peer (a hang guard, not a timing)."""
        writers = [self.clock, self.tf, *self.odom, *self.scan, *self.goal]
        deadline = time.monotonic() + 30
        while not (all(w.get_publication_matched_status().current_count for w in writers)
                   and all(r.get_subscription_matched_status().current_count
                           for r in self.cmd_vel)):
            assert peer.poll() is None and time.monotonic() < deadline, finish_peer(peer)
            time.sleep(0.01)

    def publish(self, t: float) -> None:
        self.clock.write(Clock(stamp(t)))
        transforms = []
        for i, robot in enumerate(self.robots):
            sx, sy, syaw = robot.start
            transforms.append(TransformStamped(Header(stamp(t), "map"), f"robot_{i}/odom",
                                               Transform(Vector3(sx, sy), quaternion(syaw))))
        self.tf.write(TFMessage(transforms))
        for i, robot in enumerate(self.robots):
            x, y, yaw = robot.in_odom()
            self.scan[i].write(LaserScan(Header(stamp(t), f"robot_{i}/base_scan"), -1.5, 1.5,
                                         0.5, 0.0, DT, 0.1, 8.0, [8.0] * 7))
            self.odom[i].write(Odometry(Header(stamp(t), f"robot_{i}/odom"),
                                        f"robot_{i}/base_link",
                                        PoseWithCovariance(Pose(Point(x, y), quaternion(yaw)))))

    def twists(self, peer: subprocess.Popen[str]) -> list[list[Twist]] | None:
        """Each robot's Twists for this step; None once the peer has ended."""
        received: list[list[Twist]] = [[] for _ in self.robots]
        deadline = time.monotonic() + 20
        while not all(received):
            ended = peer.poll() is not None
            for reader, got in zip(self.cmd_vel, received, strict=True):
                got.extend(self.valid(reader))
            if ended and not all(received):
                return None
            assert time.monotonic() < deadline, "no Twist within 20 s"
            time.sleep(0.001)
        time.sleep(0.005)  # a second Twist for the same odometry would arrive with the first
        for reader, got in zip(self.cmd_vel, received, strict=True):
            got.extend(self.valid(reader))
        return received

    @staticmethod
    def valid(reader: DataReader) -> list[Twist]:
        """The Twists taken, without the "no writers" notice of a peer that has ended."""
        return [sample for sample in reader.take(N=10) if isinstance(sample, Twist)]


@pytest.fixture(scope="module")
def peer_binary() -> Path:
    return build_peer()


@pytest.fixture
def participant() -> Iterator[DomainParticipant]:
    """A Cyclone DDS participant on a domain of this test's own, loopback only."""
    domain_id = next_domain()
    domain = Domain(domain_id, CYCLONE_LOOPBACK)  # held until the test ends
    yield DomainParticipant(domain_id)
    del domain


def test_the_peer_builds_and_rejects_bad_arguments(peer_binary: Path) -> None:
    assert peer_binary.is_file()
    done = subprocess.run([str(peer_binary), "--robots", "two"], env=peer_environment(201),
                          capture_output=True, text=True, timeout=30, check=False)
    assert done.returncode == 2
    assert done.stderr.startswith("mimics_ros2_peer: error: --robots expects an integer >= 1")
    env = {**peer_environment(201)}
    del env["FASTRTPS_DEFAULT_PROFILES_FILE"]  # never on Fast DDS's default (all interfaces)
    done = subprocess.run([str(peer_binary), "--robots", "1"], env=env, capture_output=True,
                          text=True, timeout=30, check=False)
    assert done.returncode == 2 and "FASTRTPS_DEFAULT_PROFILES_FILE" in done.stderr


def test_the_peer_drives_two_unicycles_home_in_lockstep(peer_binary: Path,
                                                       participant: DomainParticipant) -> None:
    robots = [Unicycle(0.5, -1.0, 2.5, goal=(2.0, 1.0)), Unicycle(1.0, 1.5, -0.7, goal=(-1.0, 0.5))]
    first_expected = [expected_command(robot) for robot in robots]
    sim = FakeSimulator(participant, robots)
    peer = start_peer(peer_binary, participant.domain_id, 2, "--steps", "400")
    sim.wait_for_peer(peer)
    per_step: list[list[Twist]] = []
    published = []
    for step in range(400):
        sim.publish(step * DT)
        published.append([(robot.x, robot.y) for robot in robots])
        answers = sim.twists(peer)
        if answers is None:
            break
        per_step.append([twists[-1] for twists in answers])
        assert [len(twists) for twists in answers] == [1, 1], f"step {step}: one Twist each"
        for robot, twist in zip(robots, per_step[-1], strict=True):
            robot.move(twist.linear.x, twist.angular.z)
    status, out, err = finish_peer(peer)
    assert status == 0, out + err
    for i, robot in enumerate(robots):
        # the peer turned odometry into a map pose, as the simulator's truth says
        assert per_step[0][i].linear.x == pytest.approx(first_expected[i][0], abs=1e-9)
        assert per_step[0][i].angular.z == pytest.approx(first_expected[i][1], abs=1e-9)
        assert math.hypot(robot.x - robot.goal[0], robot.y - robot.goal[1]) < GOAL_TOLERANCE
        assert (per_step[-1][i].linear.x, per_step[-1][i].angular.z) == (0.0, 0.0)
        x, y, gx, gy = final_poses(out)[i]
        assert (gx, gy) == pytest.approx(robot.goal, abs=1e-6)
        # its last pose is one the simulator published (it may end before the last answer)
        assert any((x, y) == pytest.approx(poses[i], abs=1e-5) for poses in published[-2:])
    # one Twist per odometry message, by the peer's own count too
    counts = answered(err)
    assert sorted(counts) == [0, 1], err
    for odometry, twists in counts.values():
        # (the last Twist may be on its way when the peer ends)
        assert odometry == twists and len(per_step) <= twists <= len(per_step) + 1


def flat(message: Any, key: str = "") -> dict[str, Any]:
    """``message``'s fields as the peer's ``--echo`` spells them: ``a.b=value``."""
    if is_dataclass(message):
        out: dict[str, Any] = {}
        for item in fields(message):
            out |= flat(getattr(message, item.name), f"{key}.{item.name}".lstrip("."))
        return out
    if isinstance(message, list) and message and is_dataclass(message[0]):
        out = {f"{key}.size": len(message)}
        for i, item in enumerate(message):
            out |= flat(item, f"{key}[{i}]")
        return out
    return {key: message}


def parse_echo(value: str) -> Any:
    if value.startswith('"'):
        return value[1:-1]
    if value.startswith("["):
        return [float(number) for number in value[1:-1].split(",") if number]
    return int(value) if value.lstrip("-").isdigit() else float(value)


def same(sent: Any, echoed: Any) -> bool:
    """Bit for bit: a float32 field's 9 printed digits give back its float32 exactly, a
    double's 17 digits its double. (The float32 fields are sent float32-exact values; values
    that are not float32-exact, as most of the doubles sent, are compared as doubles.)"""
    if isinstance(sent, list):
        return len(sent) == len(echoed) and all(map(same, sent, echoed))
    if isinstance(sent, float):
        if math.isnan(sent):
            return math.isnan(echoed)
        single = float(np.float32(sent))
        return (np.float32(echoed) == np.float32(sent)) if single == sent else echoed == sent
    return bool(sent == echoed)


def test_field_values_round_trip_exactly_and_type_names_are_ros2s(
        peer_binary: Path, participant: DomainParticipant) -> None:
    t = stamp(12.345678901)
    ranges = [float(np.float32(value)) for value in np.linspace(0.12, 7.9, 360)]
    ranges[10], ranges[11] = math.inf, math.nan  # no return, invalid reading
    singles = [float(np.float32(value))
               for value in (-math.pi, math.pi, math.tau / 360, 1e-5, 0.1, 0.12, 8.0)]
    scan = LaserScan(Header(t, "robot_0/base_scan"), *singles, ranges,
                     [float(i % 7) for i in range(360)])
    odometry = Odometry(Header(t, "robot_0/odom"), "robot_0/base_link",
                        PoseWithCovariance(Pose(Point(1 / 3, -2 / 7, 1e-300),
                                                Quaternion(0.0, 0.0, math.sin(0.4), math.cos(0.4))),
                                           [i / 9 for i in range(36)]),
                        TwistWithCovariance(Twist(Vector3(0.3, math.e, -0.0),
                                                  Vector3(0.0, 0.0, -math.pi / 5)),
                                            [-i / 11 for i in range(36)]))
    clock = Clock(t)
    tf = TFMessage([TransformStamped(Header(t, "map"), "robot_0/odom",
                                     Transform(Vector3(1.5, -0.25), quaternion(0.7))),
                    TransformStamped(Header(t, "robot_0/odom"), "robot_0/base_link",
                                     Transform(Vector3(1 / 3, -2 / 7), quaternion(0.8)))])
    goal = PoseStamped(Header(t, "map"), Pose(Point(4.25, -1.5)))
    sent = {"rt/robot_0/scan": ("sensor_msgs::msg::dds_::LaserScan_", scan),
            "rt/robot_0/odom": ("nav_msgs::msg::dds_::Odometry_", odometry),
            "rt/clock": ("rosgraph_msgs::msg::dds_::Clock_", clock),
            "rt/tf": ("tf2_msgs::msg::dds_::TFMessage_", tf),
            "rt/robot_0/goal": ("geometry_msgs::msg::dds_::PoseStamped_", goal)}
    sim = FakeSimulator(participant, [Unicycle(0.0, 0.0, 0.0, goal=(4.25, -1.5))])
    sim.goal[0].write(goal)
    peer = start_peer(peer_binary, participant.domain_id, 1, "--echo", "--echo-count", "1")
    sim.wait_for_peer(peer)
    deadline = time.monotonic() + 30
    while peer.poll() is None and time.monotonic() < deadline:  # best effort: say it again
        sim.scan[0].write(scan)
        sim.odom[0].write(odometry)
        sim.clock.write(clock)
        sim.tf.write(tf)
        time.sleep(0.02)
    status, out, err = finish_peer(peer)
    assert status == 0, out + err
    echoed = {}
    writers = set()
    for line in out.splitlines():
        words = line.split(" ")
        if words[0] == "echo":
            echoed[words[1]] = (words[2], {k: parse_echo(v) for k, v in
                                           (word.split("=", 1) for word in words[3:])})
        elif words[0] == "writer":
            writers.add((words[1], words[2]))
    assert set(echoed) == set(sent)
    for topic, (type_name, message) in sent.items():
        assert (topic, type_name) in writers  # what Cyclone announced, as Fast DDS saw it
        assert echoed[topic][0] == type_name
        expected = flat(message)
        assert set(echoed[topic][1]) == set(expected), topic
        for key, value in expected.items():
            assert same(value, echoed[topic][1][key]), (topic, key, value, echoed[topic][1][key])


def test_mimics_ros2_lockstep_run_driven_by_the_peer_reaches_both_goals(
        peer_binary: Path, tmp_path: Path) -> None:
    domain = next_domain()
    env = peer_environment(domain)  # loopback only, for mimics' Cyclone DDS too
    peer = start_peer(peer_binary, domain, 2, timeout=120)
    try:
        run = subprocess.run([sys.executable, "-m", "mimics", "ros2", "line", "--robots", "2",
                              "--seed", "1", "--time", "60", "--out", str(tmp_path / "run"),
                              "--robot-logs", "off"], env=env, capture_output=True, text=True,
                             timeout=180, check=False)
    finally:
        status, out, err = stop_peer(peer)
    assert run.returncode == 0, run.stdout + run.stderr + out + err
    assert status == 0, out + err
    outcome = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert (outcome["status"], outcome["reached_goal"]) == ("completed", 2), outcome
    finals = final_poses(out)
    assert sorted(finals) == [0, 1]
    scenario = tomllib.loads((tmp_path / "run" / "scenario.toml").read_text())
    trajectory = pd.read_parquet(tmp_path / "run" / "trajectory.parquet")
    for i, (x, y, gx, gy) in finals.items():
        # the goal it read on rt/robot_i/goal is the scenario's
        assert (gx, gy) == pytest.approx(scenario["robots"][i]["goal"], abs=1e-6)
        # its pose in map (odometry composed with tf's map -> robot_i/odom, the start pose
        # with a random yaw) is where mimics recorded the robot, up to odometry drift
        last = trajectory[trajectory["robot"] == i].tail(2)
        assert np.hypot(last["x"] - x, last["y"] - y).min() < 0.05, (out, last)
        odometry, twists = answered(err)[i]
        assert odometry == twists > 0, err
