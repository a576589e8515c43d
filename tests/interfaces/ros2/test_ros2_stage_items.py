"""What a Stage node sees under ``mimics ros2 --names stage`` (issue 49, item 5), over
loopback with the test's own ROS 2 types: no ``map -> odom`` on ``/tf`` unless
``--publish-map-odom``; scans with stage_ros' intensities (1.0 where a beam hit
something, 0.0 where not, whose range is ``range_max``); a robot driven into a wall
stalls there, active, ``is_crashed`` 1 while stalled and 0 once it backs away; robots
that reached their goal (or, with ``on_collision = "deactivate"``, collided) go on
publishing, still.

Independent truths: the run's records (statuses, poses, the recorded scans' hits), and
Stage's ranger as stage_ros publishes it.
"""

# no `from __future__ import annotations`: Cyclone reads the field types at run time
import json
import subprocess
import sys
from collections import defaultdict
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from cyclonedds.core import InstanceState, ReadCondition, SampleState, ViewState, WaitSet
from cyclonedds.domain import DomainParticipant
from cyclonedds.idl import IdlStruct
from cyclonedds.pub import DataWriter
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic

from mimics.records.run_folder import load_run
from mimics.world.robot_types import PIONEER_2DX
from tests.interfaces.ros.test_stage_world_items import SCENARIO, STALLED_STEPS
from tests.interfaces.ros2.loopback import dds_environment, loopback_here, next_domain
from tests.interfaces.ros2.observer import STREAM, WRITER, watch_until_done
from tests.interfaces.ros2.ros2_types import (
    Header,
    Int8,
    LaserScan,
    Odometry,
    TFMessage,
    Twist,
    Vector3,
)

DT, SECONDS = 0.1, 4.0
TWISTS = ((0.3, 0.0), (0.3, 0.0), (0.0, 0.0))  # robot 0 to its goal, 1 into the wall
BACKS = {1: (-0.3, 0.0)}  # robot 1 backs away once it has been stalled STALLED_STEPS steps


@dataclass
class Seen:
    folder: Path
    returncode: int = -1
    stderr: str = ""
    samples: dict = field(default_factory=lambda: defaultdict(list))


def observe(tmp_path: Path, *options: str, seconds: float) -> Seen:
    """``mimics ros2 SCENARIO --names stage --lockstep`` observed on loopback: every robot's
    odom (answered with its twist), ground truth, scan and stall flag, and ``/tf``."""
    scenario = tmp_path / "stage_items.toml"
    scenario.write_text(SCENARIO)
    domain = next_domain()
    seen = Seen(tmp_path / "run")
    with loopback_here():
        participant = DomainParticipant(domain)
        readers = {"tf": DataReader(participant, Topic(participant, "rt/tf", TFMessage),
                                    qos=STREAM)}
        commands = {}
        for i in range(3):
            robot = f"rt/robot_{i}/"
            for kind, name, kind_type in (("odom", "odom", Odometry),
                                          ("truth", "base_pose_ground_truth", Odometry),
                                          ("scan", "base_scan", LaserScan),
                                          ("stall", "is_crashed", Int8)):
                readers[f"{kind} {i}"] = DataReader(
                    participant, Topic(participant, robot + name, kind_type), qos=STREAM)
            commands[i] = DataWriter(participant, Topic(participant, robot + "cmd_vel",
                                                        Twist), qos=WRITER)
        waits = WaitSet(participant)
        for reader in readers.values():
            waits.attach(ReadCondition(reader, SampleState.NotRead | ViewState.Any
                                       | InstanceState.Any))
        process = subprocess.Popen(
            [sys.executable, "-m", "mimics", "ros2", str(scenario), "--names", "stage",
             "--lockstep", "--time", str(seconds), "--record-scans", "--robot-logs", "off",
             "--startup-grace", "1", "--timeout", "20", "--out", str(seen.folder), *options],
            env=dds_environment(domain), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
            text=True)
        try:
            seen.returncode, seen.stderr = watch_until_done(
                process, waits, lambda: _take(readers, commands, seen), 90)
        finally:
            participant.__del__()
    return seen


def _take(readers: dict, commands: dict, seen: Seen) -> None:
    for key, reader in readers.items():
        for sample in reader.take(64):
            if not isinstance(sample, IdlStruct):  # a writer that has gone: no data
                continue
            seen.samples[key].append(sample)
            if key.startswith("odom "):  # lockstep: answer the step
                robot = int(key.split()[1])
                stalled = sum(flag.data for flag in seen.samples[f"stall {robot}"])
                speed, turn = (BACKS[robot] if robot in BACKS and stalled >= STALLED_STEPS
                               else TWISTS[robot])
                commands[robot].write(
                    Twist(Vector3(speed, 0.0, 0.0), Vector3(0.0, 0.0, turn)))


def _step(header: Header) -> int:
    return round((header.stamp.sec + header.stamp.nanosec * 1e-9) / DT)


def _pairs(seen: Seen) -> set[tuple[str, str]]:
    return {(frame.header.frame_id, frame.child_frame_id)
            for message in seen.samples["tf"] for frame in message.transforms}


@pytest.fixture(scope="module")
def stage_run(tmp_path_factory: pytest.TempPathFactory) -> Seen:
    seen = observe(tmp_path_factory.mktemp("ros2_stage"), seconds=SECONDS)
    assert seen.returncode == 0, seen.stderr
    return seen


@pytest.fixture(scope="module")
def deactivating_run(tmp_path_factory: pytest.TempPathFactory) -> Seen:
    seen = observe(tmp_path_factory.mktemp("ros2_stage"), "--param", "on_collision=deactivate",
                   seconds=SECONDS)
    assert seen.returncode == 0, seen.stderr
    return seen


def test_no_map_to_odom_by_default_under_stage_names(stage_run: Seen) -> None:
    pairs = _pairs(stage_run)
    assert ("robot_0/odom", "robot_0/base_footprint") in pairs
    assert not any(parent == "map" for parent, _ in pairs)
    summary = json.loads((stage_run.folder / "summary.json").read_text())
    assert summary["ros2"]["publish_map_odom"] is False


def test_publish_map_odom_adds_it(tmp_path: Path) -> None:
    seen = observe(tmp_path, "--publish-map-odom", seconds=0.5)
    assert seen.returncode == 0, seen.stderr
    assert {("map", f"robot_{i}/odom") for i in range(3)} <= _pairs(seen)


def test_intensities_are_stage_ros(stage_run: Seen) -> None:
    both = 0
    for i in range(3):
        for scan in stage_run.samples[f"scan {i}"]:
            ranges, intensities = np.array(scan.ranges), np.array(scan.intensities)
            assert len(intensities) == len(ranges) == 180
            hit = ranges < scan.range_max
            np.testing.assert_array_equal(intensities, np.where(hit, 1.0, 0.0))
            both += bool(hit.any() and not hit.all())
    assert both > 0
    recorded = load_run(stage_run.folder).scans.robot(0)
    published = {_step(scan.header): scan for scan in stage_run.samples["scan 0"]}
    for step, hits in zip(recorded.steps, recorded.hits, strict=True):
        np.testing.assert_array_equal(published[step].intensities, np.where(hits, 1.0, 0.0))


def test_a_robot_driven_into_a_wall_stalls_active_and_backs_away(stage_run: Seen) -> None:
    trajectory = pd.read_parquet(stage_run.folder / "trajectory.parquet")
    mine = trajectory[trajectory.robot == 1].sort_values("step")
    last = round(SECONDS / DT)
    assert mine.step.tolist() == list(range(last + 1)) and (mine.status == 0).all()
    assert (mine.x + PIONEER_2DX.length / 2 < 10.0).all()  # the wall at x = 10: not crossed
    flags = [m.data for m in stage_run.samples["stall 1"]]  # in order: one writer, reliable
    assert len(flags) == last + 1
    raised = [k for k, flag in enumerate(flags) if flag == 1]
    assert len(raised) >= STALLED_STEPS and raised[0] > 0  # free, then stalled...
    after = flags[raised[-1] + 1:]
    assert len(after) >= 10 and not any(after)  # ...then 0 again, backing away
    assert float(mine.x.iloc[-1]) < float(mine[mine.step == raised[-1]].x.iloc[0]) - 0.2
    summary = json.loads((stage_run.folder / "summary.json").read_text())
    assert summary["collisions"] == summary["wall_collisions"] == 1
    assert summary["parameters"]["on_collision"] == "stall"


@pytest.mark.parametrize(("robot", "status", "flag", "which"),
                         [(0, 1, 0, "stage_run"), (1, 2, 1, "deactivating_run")])
def test_stopped_robots_keep_publishing_still(request: pytest.FixtureRequest, robot: int,
                                              status: int, flag: int, which: str) -> None:
    stage_run: Seen = request.getfixturevalue(which)
    trajectory = pd.read_parquet(stage_run.folder / "trajectory.parquet")
    mine = trajectory[trajectory.robot == robot]
    stop = int(mine[mine.status == status].step.min())
    last = round(SECONDS / DT)
    assert stop + round(2.0 / DT) <= last
    for kind in ("odom", "truth", "scan"):
        steps = sorted(_step(m.header) for m in stage_run.samples[f"{kind} {robot}"])
        assert steps == list(range(last + 1)), kind
    for kind in ("odom", "truth"):
        after = [m for m in stage_run.samples[f"{kind} {robot}"] if _step(m.header) >= stop]
        assert all(m.twist.twist.linear.x == 0 and m.twist.twist.angular.z == 0 for m in after)
        assert len({(m.pose.pose.position.x, m.pose.pose.position.y) for m in after}) == 1
    flags = [m.data for m in stage_run.samples[f"stall {robot}"]]
    assert len(flags) == last + 1 and flags[-1] == flag and flags == sorted(flags)
