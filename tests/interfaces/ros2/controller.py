"""A ROS 2 controller over Cyclone DDS, written from ROS 2's conventions (not mimics' code).

``python -m tests.interfaces.ros2.controller ROBOTS [MARK]`` (domain from
``ROS_DOMAIN_ID``, Cyclone's settings from ``CYCLONEDDS_URI``): per robot it
reads ``rt/robot_i/ground_truth`` (``nav_msgs/Odometry`` in ``map``) and the
transient-local ``rt/robot_i/goal``, and answers each ground truth with one
``geometry_msgs/Twist`` on ``rt/robot_i/cmd_vel`` turning towards the goal
and driving to it: a function of that step's message only, so that two
lockstep runs give one trajectory. Runs until killed; after 30 answers it
creates the file ``MARK`` when given (the run is then under way).
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from cyclonedds.core import InstanceState, ReadCondition, SampleState, ViewState, WaitSet
from cyclonedds.domain import DomainParticipant
from cyclonedds.internal import InvalidSample
from cyclonedds.pub import DataWriter
from cyclonedds.qos import Policy, Qos
from cyclonedds.sub import DataReader
from cyclonedds.topic import Topic
from cyclonedds.util import duration

from tests.interfaces.ros2.ros2_types import Odometry, PoseStamped, Twist, Vector3

RELIABLE = Policy.Reliability.Reliable(max_blocking_time=duration(milliseconds=100))
STREAM = Qos(RELIABLE, Policy.History.KeepLast(10))
LATCHED = Qos(RELIABLE, Policy.Durability.TransientLocal, Policy.History.KeepLast(1))
WRITER = Qos(RELIABLE, Policy.History.KeepLast(10),
             Policy.DataRepresentation(use_cdrv0_representation=True))


def twist_towards(truth: Odometry, goal: tuple[float, float]) -> Twist:
    """Turn towards the goal, drive when facing it, slow down near it."""
    position, q = truth.pose.pose.position, truth.pose.pose.orientation
    heading = math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))
    dx, dy = goal[0] - position.x, goal[1] - position.y
    error = math.remainder(math.atan2(dy, dx) - heading, math.tau)
    speed = min(2.0, math.hypot(dx, dy)) * max(0.0, math.cos(error))
    return Twist(Vector3(speed, 0.0, 0.0), Vector3(0.0, 0.0, 2.0 * error))


def main(robots: int, mark: str | None) -> None:
    participant = DomainParticipant(int(os.environ.get("ROS_DOMAIN_ID", "0")))
    truths, goals, commands = [], [], []
    for i in range(robots):
        truths.append(DataReader(participant, Topic(
            participant, f"rt/robot_{i}/ground_truth", Odometry), qos=STREAM))
        goals.append(DataReader(participant, Topic(
            participant, f"rt/robot_{i}/goal", PoseStamped), qos=LATCHED))
        commands.append(DataWriter(participant, Topic(
            participant, f"rt/robot_{i}/cmd_vel", Twist), qos=WRITER))
    waits = WaitSet(participant)
    mask = SampleState.NotRead | ViewState.Any | InstanceState.Any
    for reader in truths:
        waits.attach(ReadCondition(reader, mask))
    known: dict[int, tuple[float, float]] = {}
    answers = 0
    while True:
        waits.wait(duration(milliseconds=200))
        for i, reader in enumerate(truths):
            for truth in reader.take(16):
                if isinstance(truth, InvalidSample):
                    continue
                deadline = time.monotonic() + 10
                while i not in known and time.monotonic() < deadline:
                    for goal in goals[i].read(1):
                        known[i] = (goal.pose.position.x, goal.pose.position.y)
                    time.sleep(0.005)
                commands[i].write(twist_towards(truth, known[i]))
                answers += 1
                if mark is not None and answers == 30:
                    open(mark, "w").close()


# -- for the tests that run it beside ``mimics ros2`` -------------------------------------


def wait_until_under_way(mark: Path, run: subprocess.Popen[Any], limit: float) -> None:
    """Until the controller has created ``mark`` (30 answers), ``run`` still going."""
    deadline = time.monotonic() + limit
    while not mark.exists():
        assert run.poll() is None, run.communicate()
        assert time.monotonic() < deadline, "the run did not start"
        time.sleep(0.02)


def end_all(*processes: subprocess.Popen[Any]) -> None:
    """Kill and reap whichever of ``processes`` is still running (the test has ended)."""
    for process in processes:
        if process.poll() is None:
            process.kill()
            process.communicate()


if __name__ == "__main__":
    main(int(sys.argv[1]), sys.argv[2] if len(sys.argv) > 2 else None)
