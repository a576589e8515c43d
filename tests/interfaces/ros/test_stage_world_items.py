"""What a Stage node sees under ``--names stage``, against a real ``rosmaster`` (issue 49,
item 5): no ``map -> odom`` unless ``--publish-map-odom``; a robot driven into a wall
stalls there, active, with Stage's stall flag on ``is_crashed`` (1 while stalled, 0 once
it backs away); robots that reach their goal (or, with ``on_collision = "deactivate"``,
collide) stay and keep publishing, still; scans carry stage_ros' intensities and
``range_max`` where a beam hit nothing.

Independent truths: the run's own records (the trajectory's statuses and poses, the
recorded scans' hit masks), and Stage's ranger as stage_ros publishes it (an intensity
of 1.0 for a beam that hit a model, the default ``ranger_return``, and 0.0 with no
return, whose range is ``range_max``).
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mimics.interfaces.ros.bridge_core import BridgeOptions, load_run_scenario, options_record
from mimics.records.run_folder import load_run
from mimics.world.robot_types import PIONEER_2DX
from tests.interfaces.ros.helpers import SYSTEM_PYTHON, running_master, with_node
from tests.system_packages import require

DT = 0.1
#: robot 0 has its goal 0.5 m ahead, robot 1 drives into the wall at x = 10 (and, stalled
#: there for 5 steps, backs away: "back"), robot 2 stands still (no goal): the run goes on
#: (a run whose robots all stop ends)
SCENARIO = """
name = "stage_items"
map = { segments = [[10, 0, 10, 6]], bounds = [0, 0, 20, 20] }
robots = [
  { type = "Pioneer2DX", x = 4.0, y = 3.0, goal = [4.5, 3.0] },
  { type = "Pioneer2DX", x = 9.6, y = 1.0 },
  { type = "Pioneer2DX", x = 5.0, y = 15.0 },
]
[settings]
time_limit = 60.0
noise = "off"
"""
TWISTS = "0.3,0;0.3,0,back;0,0"
STALLED_STEPS = 5  # is_crashed reads 1 this often before the node backs robot 1 away

#: a node as a Stage user writes one: it answers each robot's odom with a fixed cmd_vel
#: and logs what it receives (run with the system's Python, where rospy is)
NODE = r'''
import json, sys, threading
import rospy
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import LaserScan
from std_msgs.msg import Int8
from tf2_msgs.msg import TFMessage

log_path, robots, twists = sys.argv[1], int(sys.argv[2]), sys.argv[3]
rospy.init_node("stage_items_node")
out, lock = open(log_path, "w"), threading.Lock()

def log(entry):
    with lock:
        out.write(json.dumps(entry) + "\n")
        out.flush()

def stamp(message):
    return message.header.stamp.to_nsec()

def on_odom(message, args):
    robot, kind = args
    log({"kind": kind, "robot": robot, "stamp": stamp(message),
         "xy": [message.pose.pose.position.x, message.pose.pose.position.y],
         "twist": [message.twist.twist.linear.x, message.twist.twist.angular.z]})
    if kind == "odom":
        backing = robot in backs and stalls.get(robot, 0) >= 5
        commands[robot].publish(backs[robot] if backing else answers[robot])

def on_scan(message, robot):
    log({"kind": "scan", "robot": robot, "stamp": stamp(message),
         "range_max": message.range_max, "ranges": list(message.ranges),
         "intensities": list(message.intensities)})

def on_stall(message, robot):
    log({"kind": "stall", "robot": robot, "data": message.data})
    stalls[robot] = stalls.get(robot, 0) + message.data

def on_tf(message):
    log({"kind": "tf", "pairs": [[t.header.frame_id, t.child_frame_id]
                                 for t in message.transforms]})

commands, answers, backs, stalls = [], [], {}, {}
for robot, pair in enumerate(twists.split(";")):
    twist = Twist()
    speed, turn, *how = pair.split(",")
    twist.linear.x, twist.angular.z = float(speed), float(turn)
    answers.append(twist)
    if how == ["back"]:  # reverse once stalled: Stage's habit of backing off a wall
        backs[robot] = Twist()
        backs[robot].linear.x = -float(speed)
    prefix = "robot_%d/" % robot
    commands.append(rospy.Publisher(prefix + "cmd_vel", Twist, queue_size=10,
                                    tcp_nodelay=True))
    rospy.Subscriber(prefix + "odom", Odometry, on_odom, (robot, "odom"), tcp_nodelay=True)
    rospy.Subscriber(prefix + "base_pose_ground_truth", Odometry, on_odom, (robot, "truth"))
    rospy.Subscriber(prefix + "base_scan", LaserScan, on_scan, robot)
    rospy.Subscriber(prefix + "is_crashed", Int8, on_stall, robot)
rospy.Subscriber("/tf", TFMessage, on_tf)
rospy.spin()
'''


def run(env: dict[str, str], tmp_path: Path, name: str, *options: str,
        seconds: float) -> tuple[pd.DataFrame, Path]:
    """``mimics ros`` on the scenario with the node; the node's log and the run folder."""
    scenario, node = tmp_path / "stage_items.toml", tmp_path / "stage_items_node.py"
    scenario.write_text(SCENARIO)
    node.write_text(NODE)
    log, folder = tmp_path / f"{name}.jsonl", tmp_path / name
    bridge, output = with_node(
        env, [SYSTEM_PYTHON, str(node), str(log), "3", TWISTS], str(scenario), "--names",
        "stage", "--lockstep", "--time", str(seconds), "--record-scans", "--robot-logs", "off",
        "--out", str(folder), *options)
    assert bridge.returncode == 0, bridge.stdout + bridge.stderr + output
    table = pd.DataFrame([json.loads(line) for line in log.read_text().splitlines()])
    if "stamp" in table:
        table["step"] = (table["stamp"] / 1e9 / DT).round().astype("Int64")
    return table, folder


def tf_pairs(messages: pd.DataFrame) -> set[tuple[str, str]]:
    return {tuple(pair) for pairs in messages[messages.kind == "tf"].pairs for pair in pairs}


def test_map_odom_is_on_request_by_default_only_under_mimics_names() -> None:
    assert BridgeOptions(names="mimics").map_odom
    assert not BridgeOptions(names="stage").map_odom
    assert BridgeOptions(names="stage", publish_map_odom=True).map_odom
    assert not BridgeOptions(names="mimics", publish_map_odom=False).map_odom
    assert options_record(BridgeOptions(names="stage"))["publish_map_odom"] is False


def test_stage_names_stall_robots_unless_the_scenario_or_a_parameter_says(tmp_path) -> None:
    stage, mimics = BridgeOptions(names="stage"), BridgeOptions(names="mimics")
    plain = tmp_path / "plain.toml"
    plain.write_text(SCENARIO)
    chosen = tmp_path / "chosen.toml"
    chosen.write_text(SCENARIO.replace('noise = "off"', 'noise = "off"\non_collision = '
                                       '"deactivate"'))

    def rule(scenario, options, params=None):
        return load_run_scenario(scenario, options, params, 0).settings.on_collision

    assert rule(plain, stage) == rule("line", stage, {"robots": 2}) == "stall"
    assert load_run_scenario(plain, stage, None, 0).parameters["on_collision"] == "stall"
    assert rule(chosen, stage) == "deactivate"  # the file's [settings] says
    assert rule(plain, stage, {"on_collision": "deactivate"}) == "deactivate"  # --param says
    assert rule(plain, mimics) == rule("line", mimics, {"robots": 2}) == "deactivate"
    # Stage removes no robot for waiting: neither does a run under its names, unless asked

    def removes_waiting(scenario, options, params=None):
        return load_run_scenario(scenario, options, params, 0).settings.deactivate_on_deadlock

    assert removes_waiting(plain, stage) is False and removes_waiting(plain, mimics) is True
    assert removes_waiting(plain, stage, {"deactivate_on_deadlock": True}) is True


@pytest.fixture(scope="module")
def ros_env_module(tmp_path_factory: pytest.TempPathFactory) -> Iterator[dict[str, str]]:
    """A fresh ``rosmaster`` for this module's runs (as the conftest's ``ros_env``)."""
    require("ros")
    with running_master(tmp_path_factory.mktemp("ros_home")) as env:
        yield env


@pytest.fixture(scope="module")
def stage_run(ros_env_module: dict[str, str],
              tmp_path_factory: pytest.TempPathFactory) -> tuple[pd.DataFrame, Path]:
    """The default stage run: 4 s; robot 0 reaches its goal, robot 1 stalls at the wall."""
    return run(ros_env_module, tmp_path_factory.mktemp("stage_items"), "default", seconds=4.0)


@pytest.fixture(scope="module")
def deactivating_run(ros_env_module: dict[str, str],
                     tmp_path_factory: pytest.TempPathFactory) -> tuple[pd.DataFrame, Path]:
    """The stage run with ``--param on_collision=deactivate``: robot 1's collision ends its
    run."""
    return run(ros_env_module, tmp_path_factory.mktemp("stage_items"), "deactivating",
               "--param", "on_collision=deactivate", seconds=4.0)


def test_no_map_to_odom_under_stage_names_by_default(stage_run) -> None:
    messages, folder = stage_run
    pairs = tf_pairs(messages)
    assert ("robot_0/odom", "robot_0/base_footprint") in pairs  # /tf did come...
    assert not any(parent == "map" for parent, _ in pairs)  # ...with no map -> odom
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["ros"]["publish_map_odom"] is False


def test_publish_map_odom_adds_it(ros_env_module, tmp_path) -> None:
    messages, folder = run(ros_env_module, tmp_path, "with_map_odom", "--publish-map-odom",
                           seconds=0.5)
    pairs = tf_pairs(messages)
    assert {("map", f"robot_{i}/odom") for i in range(3)} <= pairs
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["ros"]["publish_map_odom"] is True


def _stopped_at(folder: Path, robot: int, status: int) -> int:
    """The first step at which the trajectory records ``robot`` with ``status``."""
    trajectory = pd.read_parquet(folder / "trajectory.parquet")
    mine = trajectory[trajectory.robot == robot].sort_values("step")
    return int(mine[mine.status == status].step.iloc[0])


@pytest.mark.parametrize(("robot", "status", "flag", "which"),
                         [(0, 1, 0, "stage_run"), (1, 2, 1, "deactivating_run")])
def test_stopped_robots_stay_and_keep_publishing_still(request, robot, status, flag,
                                                       which) -> None:
    """Robot 0 reached its goal (status 1); robot 1 hit the wall (status 2) where
    collisions deactivate: both go on publishing odom, ground truth and scans, still, 2 s
    and more after, and their stall flag (Stage's: 1 once collided)."""
    messages, folder = request.getfixturevalue(which)
    stop = _stopped_at(folder, robot, status)
    last = round(4.0 / DT)
    assert stop + round(2.0 / DT) <= last  # the run went on 2 s past the stop
    mine = messages[messages.robot == robot]
    for kind in ("odom", "truth", "scan"):
        steps = sorted(mine[mine.kind == kind].step)
        assert steps == list(range(last + 1)), kind  # every step, to the end
    trajectory = pd.read_parquet(folder / "trajectory.parquet").set_index(["robot", "step"])
    still = trajectory.loc[robot].loc[stop, ["x", "y"]].to_numpy(dtype=float)
    for kind in ("odom", "truth"):
        after = mine[(mine.kind == kind) & (mine.step >= stop)]
        assert np.array(after.twist.tolist()) == pytest.approx(np.zeros((len(after), 2)))
        poses = np.array(after.xy.tolist())
        np.testing.assert_array_equal(poses, np.repeat(poses[:1], len(poses), axis=0))
    truth = mine[(mine.kind == "truth") & (mine.step == last)]
    np.testing.assert_allclose(truth.xy.iloc[0], still, atol=1e-12)
    # the scan it had before it stopped, held (the engine scans active robots only)
    scans = mine[mine.kind == "scan"].set_index("step")
    held = scans.loc[stop - 1, "ranges"]
    assert all(scans.loc[step, "ranges"] == held for step in range(stop, last + 1))
    flags = mine[mine.kind == "stall"].data.tolist()
    assert len(flags) >= last + 1 - stop and flags[-1] == flag
    assert flags == sorted(flags)  # once stalled, stalled


def test_a_robot_driven_into_a_wall_stalls_active_and_backs_away(stage_run) -> None:
    """Robot 1 stalls at the wall (the stage names' ``on_collision = "stall"``): active
    throughout, never through the wall, ``is_crashed`` 1 while stalled, then 0 as it backs
    away, and the summary counts one wall collision."""
    messages, folder = stage_run
    trajectory = pd.read_parquet(folder / "trajectory.parquet")
    mine = trajectory[trajectory.robot == 1].sort_values("step")
    last = round(4.0 / DT)
    assert mine.step.tolist() == list(range(last + 1))
    assert (mine.status == 0).all()  # never deactivated
    assert (mine.x + PIONEER_2DX.length / 2 < 10.0).all()  # the wall at x = 10: not crossed
    flags = messages[(messages.kind == "stall") & (messages.robot == 1)].data.tolist()
    assert len(flags) == last + 1
    raised = [k for k, flag in enumerate(flags) if flag == 1]
    assert len(raised) >= STALLED_STEPS and raised[0] > 0  # free, then stalled...
    after = flags[raised[-1] + 1:]
    assert len(after) >= 10 and not any(after)  # ...then 0 again, backing away
    stalled_x = float(mine[mine.step == raised[-1]].x.iloc[0])
    assert float(mine.x.iloc[-1]) < stalled_x - 0.2  # it drove back
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["collisions"] == summary["wall_collisions"] == 1
    assert summary["parameters"]["on_collision"] == "stall"
    events = load_run(folder).events
    hits = events[events.kind == "collision"]
    assert set(hits.robot) == {1} and set(hits.other) == {-1}


def test_intensities_are_stage_ros_and_no_return_reads_range_max(stage_run) -> None:
    messages, folder = stage_run
    scans = messages[messages.kind == "scan"]
    both = 0
    for row in scans.itertuples():
        ranges, intensities = np.array(row.ranges), np.array(row.intensities)
        assert len(intensities) == len(ranges) == 180
        hit = ranges < row.range_max
        np.testing.assert_array_equal(intensities, np.where(hit, 1.0, 0.0))
        both += bool(hit.any() and not hit.all())
    assert both > 0  # scans with hits and with beams that hit nothing
    # the hits are the run's recorded ones, beam by beam
    recorded = load_run(folder).scans.robot(0)
    robot_0 = scans[scans.robot == 0].set_index("step")
    for step, hits in zip(recorded.steps, recorded.hits, strict=True):
        intensities = np.array(robot_0.loc[step, "intensities"])
        np.testing.assert_array_equal(intensities, np.where(hits, 1.0, 0.0))
