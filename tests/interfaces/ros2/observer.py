"""An observer of a live ``mimics ros2`` run, written from ROS 2's conventions in Cyclone Python.

It joins the run's domain (loopback only), lists what is published through
the DCPS builtin topic (``DcpsPublication``: topic and type names), reads
``rt/clock``, each robot's ``odom``, ``ground_truth`` and ``scan`` as raw CDR
bytes (the samples as they came off the wire, encapsulation header
included), and answers each ``odom`` with a fixed ``Twist`` per robot, so
that a lockstep run goes on.
"""

from __future__ import annotations

import subprocess
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from cyclonedds._clayer import ddspy_take
from cyclonedds.builtin import BuiltinDataReader, BuiltinTopicDcpsPublication
from cyclonedds.core import InstanceState, ReadCondition, SampleState, ViewState, WaitSet
from cyclonedds.domain import DomainParticipant
from cyclonedds.pub import DataWriter
from cyclonedds.qos import Policy, Qos
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from tests.interfaces.ros2.loopback import dds_environment, loopback_here
from tests.interfaces.ros2.ros2_types import Clock, LaserScan, Odometry, Twist, Vector3

RELIABLE = Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100))
STREAM = Qos(RELIABLE, Policy.History.KeepLast(10))
WRITER = Qos(RELIABLE, Policy.History.KeepLast(10),
             Policy.DataRepresentation(use_cdrv0_representation=True))
ANY = SampleState.Any | ViewState.Any | InstanceState.Any
#: what the observer commands robot i: (linear.x, angular.z)
TWISTS = ((0.6, 0.3), (0.4, -0.2))


@dataclass
class Observed:
    """What the observer saw: raw CDR samples per DDS topic, and the publications."""

    folder: Path
    returncode: int
    stderr: str
    publications: set[tuple[str, str]] = field(default_factory=set)
    raw: dict[str, list[bytes]] = field(default_factory=dict)


MIMICS_NAMES = ("robot_{i}/", "odom", "ground_truth", "scan")
#: stage_ros' names for a single robot: no prefix
STAGE_NAMES = ("", "odom", "base_pose_ground_truth", "base_scan")


def observe_run(folder: Path, domain: int, robots: int, arguments: list[str],
                limit: float = 90.0, names: tuple[str, ...] = MIMICS_NAMES) -> Observed:
    """Run ``mimics ros2 line`` into ``folder`` on ``domain`` while observing it; the
    robots' topics are ``names``: a prefix, then odometry, ground truth and scan."""
    with loopback_here():
        return _observe(folder, domain, robots, arguments, limit, names)


def _observe(folder: Path, domain: int, robots: int, arguments: list[str],
             limit: float, names: tuple[str, ...]) -> Observed:
    participant = DomainParticipant(domain)
    publications = BuiltinDataReader(participant, BuiltinTopicDcpsPublication)
    readers: dict[str, DataReader] = {
        "rt/clock": DataReader(participant, Topic(participant, "rt/clock", Clock), qos=STREAM)}
    commands: dict[str, DataWriter] = {}  # odometry topic: its robot's cmd_vel
    prefix, *topics = names
    for i in range(robots):
        robot = f"rt/{prefix.format(i=i)}"
        for name, kind in zip(topics, (Odometry, Odometry, LaserScan), strict=True):
            readers[robot + name] = DataReader(participant, Topic(
                participant, robot + name, kind), qos=STREAM)
        commands[robot + topics[0]] = DataWriter(participant, Topic(
            participant, f"{robot}cmd_vel", Twist), qos=WRITER)
    waits = WaitSet(participant)
    for reader in readers.values():
        waits.attach(ReadCondition(reader, SampleState.NotRead | ViewState.Any
                                   | InstanceState.Any))
    process = subprocess.Popen(
        [sys.executable, "-m", "mimics", "ros2", "line", "--robots", str(robots),
         "--out", str(folder), *arguments],
        env=dds_environment(domain), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
        text=True)
    seen = Observed(folder, -1, "", raw={topic: [] for topic in readers})

    def take() -> None:
        _take_all(readers, seen, commands)
        _publications(publications, seen)

    try:
        seen.returncode, seen.stderr = watch_until_done(process, waits, take, limit)
    finally:
        participant.__del__()
    return seen


def watch_until_done(process: subprocess.Popen[str], waits: WaitSet,
                     take: Callable[[], None], limit: float) -> tuple[int, str]:
    """Call ``take`` whenever ``waits`` wakes (at least every 0.1 s) until ``process`` ends
    or ``limit`` seconds pass, once more after; kill it if it still runs. Its return code
    and standard error."""
    deadline = time.monotonic() + limit
    try:
        while process.poll() is None and time.monotonic() < deadline:
            waits.wait(duration(milliseconds=100))
            take()
        take()
    finally:
        if process.poll() is None:
            process.kill()
        stderr = process.communicate()[1]
    return process.returncode, stderr


def _take_all(readers: dict[str, DataReader], seen: Observed,
              commands: dict[str, DataWriter]) -> None:
    for topic, reader in readers.items():
        taken = ddspy_take(reader._ref, ANY, 64)  # raw: the CDR bytes as they came
        for data, info in taken if not isinstance(taken, int) else []:
            if not info.valid_data:
                continue
            seen.raw[topic].append(bytes(data))
            if topic in commands:  # an odometry: lockstep, answer the step
                speed, turn = TWISTS[list(commands).index(topic)]
                commands[topic].write(Twist(Vector3(speed, 0.0, 0.0), Vector3(0.0, 0.0, turn)))


def _publications(reader: BuiltinDataReader, seen: Observed) -> None:
    for sample in reader.take(256):
        if sample.topic_name is not None:  # None: a writer that has gone (its key only)
            seen.publications.add((sample.topic_name, sample.type_name))
