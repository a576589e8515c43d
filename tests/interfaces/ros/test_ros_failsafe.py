"""The bridge fails safe, against a real ``rosmaster``: a dead node, a late scan
subscriber, a silent node in realtime, commands beyond the robot's limits."""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from tests.interfaces.ros.helpers import NODES, SYSTEM_PYTHON, with_node
from tests.system_packages import require

FAILSAFE = str(NODES / "failsafe_node.py")


def summary(folder: Path) -> dict:
    return json.loads((folder / "summary.json").read_text())


def notes(folder: Path, robot: int) -> pd.DataFrame:
    events = pd.read_parquet(folder / "events.parquet")
    return events[(events["kind"] == "user_message") & (events["robot"] == robot)]


def test_a_dead_node_ends_a_20_robot_lockstep_run_within_one_time_out(ros_env, tmp_path):
    folder, timeout = tmp_path / "run", 2.0
    node = [SYSTEM_PYTHON, FAILSAFE, "--mode", "die", "--robots", "20", "--at", "1.0"]
    # facing their goals, so that no robot clips a neighbour and leaves before t=1 s
    bridge, output = with_node(ros_env, node, "line", "--robots", "20", "--param",
                               "random_yaw=false", "--timeout", str(timeout),
                               "--strict-lockstep", "--out",
                               str(folder), "--robot-logs", "off")
    ended = time.time()
    assert bridge.returncode == 1, bridge.stderr + output
    died = float(output.split("died ", 1)[1].split()[0])
    run_ended = (folder / "summary.json").stat().st_mtime  # the run's record, written last
    # one deadline for the step, not one per robot (20 x 2 s = 40 s): the run
    # ends within the time-out plus a second, the process (leaving ROS) soon after
    assert run_ended - died <= timeout + 1.0, (run_ended - died, bridge.stderr)
    assert ended - died <= timeout + 5.0, (ended - died, bridge.stderr)
    last = bridge.stderr.strip().splitlines()[-1]
    assert "no command for t=1 s within 2 s (--timeout) from 20 robots: 0-19 " in last, last
    assert summary(folder)["status"] == "error"


def test_a_late_scan_subscriber_still_gets_step_0s_scan(ros_env, tmp_path):
    """Also ``mimics ros --record-scans``: the recorded scans are the ones the node got."""
    folder = tmp_path / "run"
    node = [SYSTEM_PYTHON, FAILSAFE, "--mode", "late-scan", "--at", "0.3"]
    # a room: the ranger sees walls, so the scans have hits to compare
    bridge, output = with_node(ros_env, node, "obstacle_room", "--robots", "1", "--time", "1",
                               "--timeout", "5", "--out", str(folder), "--robot-logs", "off",
                               "--record-scans")
    assert bridge.returncode == 0, bridge.stderr + output
    assert summary(folder)["status"] == "time_limit"
    received = [line.split()[1:] for line in output.splitlines() if line.startswith("scan ")]
    stamps = [float(stamp) for stamp, _ in received]
    # every step's scan, from step 0 on, once each (the node answers only with a scan)
    assert stamps == pytest.approx([step / 10 for step in range(len(stamps))])
    assert stamps[0] == 0.0 and len(stamps) >= 10
    recorded = pd.read_parquet(folder / "scans.parquet").set_index("step")
    assert recorded.index.tolist() == list(range(11))
    for step, (_, hits) in enumerate(received[:11]):
        assert int(hits) == int(recorded.loc[step, "hits"].sum()) > 0


def test_realtime_watchdog_stops_a_robot_whose_node_died(ros_env, tmp_path):
    folder, watchdog = tmp_path / "run", 0.2
    node = [SYSTEM_PYTHON, FAILSAFE, "--mode", "die", "--robots", "2", "--at", "1.0"]
    bridge, output = with_node(ros_env, node, "line", "--robots", "2", "--realtime",
                               "--time", "2.5", "--watchdog", str(watchdog), "--out",
                               str(folder), "--robot-logs", "off")
    assert bridge.returncode == 0, bridge.stderr + output
    assert summary(folder)["ros"]["watchdog"] == watchdog
    table = pd.read_parquet(folder / "trajectory.parquet")
    robot = table[table["robot"] == 0].set_index("time")
    assert robot.loc[0.5:0.9, "v_ref"].eq(0.3).all()  # driven while the node lived
    stopped = robot[(robot.index >= 1.0) & (robot["v_ref"] == 0.0)]
    # the node's last command answered t = 0.9 s; the watchdog stops the robot
    # within 0.2 s of wall time after it, i.e. at the first steps past 1.1 s
    # (one step of 0.1 s and one of slack for the loaded machine's pace)
    assert stopped.index.min() <= 0.9 + watchdog + 0.2 + 1e-9, stopped.index.min()
    assert (robot.loc[stopped.index.min():, "v_ref"] == 0.0).all()
    said = notes(folder, 0)["detail"].tolist()
    # stopped, and the node's end reported (at the stop, or once rospy sees it go)
    assert any(text.startswith("watchdog: ") and "stopping the robot (watchdog 0.2 s)" in text
               for text in said), said
    assert any("its node has gone (nothing publishes /robot_0/cmd or cmd_vel)" in text
               for text in said), said


def test_huge_commands_are_clipped_to_the_robots_limits_and_recorded(ros_env, tmp_path):
    from mimics.catalog import load_scenario

    kind = load_scenario("line", robots=2).types[0]
    folder = tmp_path / "run"
    node = [SYSTEM_PYTHON, FAILSAFE, "--mode", "huge"]
    bridge, output = with_node(ros_env, node, "line", "--robots", "2", "--time", "2.5",
                               "--out", str(folder), "--robot-logs", "off")
    assert bridge.returncode == 0, bridge.stderr + output
    table = pd.read_parquet(folder / "trajectory.parquet")
    answered = table[table["step"] >= 1]
    assert (answered["v_ref"] == kind.kv).all()  # both robots: the top speed
    assert (answered[answered["robot"] == 1]["heading_ref"] == 0.5).all()
    twist = notes(folder, 0)
    # once per simulated second, with the count of clipped commands since the last note
    assert twist["step"].tolist() == [1, 11, 21]
    assert twist["detail"].iloc[0] == (
        f"cmd_vel asked linear.x=1e+30 m/s, angular.z=-1e+30 rad/s; applied {kind.kv:g} m/s, "
        f"{-kind.kw:g} rad/s (the robot's limits)")
    assert twist["detail"].iloc[1].endswith("(10 clipped commands since the last note)")
    reference = notes(folder, 1)["detail"].iloc[0]
    assert reference == (f"cmd asked speed_ref=1e+300 m/s; applied {kind.kv:g} m/s "
                         f"(top speed {kind.kv:g} m/s)")


def test_mimics_run_ros_timeout_is_one_deadline_and_its_message_cites_it(tmp_path):
    """``ros:`` algorithms under ``mimics run``: their own master, ``--ros-timeout``."""
    require("ros")
    done = subprocess.run(
        [sys.executable, "-m", "mimics", "run", "line",
         f"ros:{FAILSAFE} --mode die --robots {{robots}} --at 1.0", "--robots", "3",
         # a deadline a loaded machine's live node keeps (failed once at 1 s under load)
         "--ros-timeout", "4", "--out", str(tmp_path / "run"), "--robot-logs", "off"],
        capture_output=True, text=True, timeout=120, check=False)
    assert done.returncode == 1, done.stdout + done.stderr
    assert ("no command for t=1 s within 4 s (--ros-timeout) from 3 robots: 0-2 "
            in done.stdout + done.stderr), done.stdout + done.stderr
    assert summary(tmp_path / "run")["status"] == "error"
    # the option belongs to ros: algorithms only
    other = subprocess.run([sys.executable, "-m", "mimics", "run", "line", "go_to_goal",
                            "--ros-timeout", "1", "--out", str(tmp_path / "other")],
                           capture_output=True, text=True, timeout=120, check=False)
    assert other.returncode == 2
    assert other.stderr.strip() == ("mimics: error: --ros-timeout: only for ros: and ros2: "
                                    "algorithms (ros:PROGRAM or ros2:PROGRAM [ARGS...])")
    assert not (tmp_path / "other").exists()


def test_bad_command_warnings_are_throttled_per_robot_with_a_count():
    require("ros")
    from mimics.interfaces.ros.system_ros import require_ros

    require_ros()
    from mimics.interfaces.ros.commands import WarningThrottle

    warn = WarningThrottle()
    assert warn(0, "cmd_vel: bad", 100.0) == "robot 0: cmd_vel: bad"
    assert warn(1, "cmd: bad", 100.1) == "robot 1: cmd: bad"  # each robot its own second
    assert [warn(0, "cmd_vel: bad", 100.0 + k / 10) for k in range(1, 10)] == [None] * 9
    assert warn(0, "cmd_vel: bad", 101.0) == (
        "robot 0: cmd_vel: bad (10 bad messages for this robot in the last 1.0 s)")
