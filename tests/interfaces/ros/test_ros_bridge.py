"""`mimics ros` against a real ``rosmaster``: the examples, determinism, bad situations."""

from __future__ import annotations

import importlib.util
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pandas as pd
import pytest

from tests.interfaces.ros.helpers import (
    EXAMPLES,
    NODES,
    SYSTEM_PYTHON,
    free_port,
    mimics_ros,
    with_node,
)
from tests.system_packages import require

# the line with every robot facing its goal (its default draws the paper's random headings)
FACING = ("--param", "random_yaw=false")


def _load_plan() -> ModuleType:
    spec = importlib.util.spec_from_file_location("scripted_plan", NODES / "scripted_plan.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


script = _load_plan()  # the scripted node's numbers


def summary(folder: Path) -> dict:
    return json.loads((folder / "summary.json").read_text())


def trajectory(folder: Path) -> pd.DataFrame:
    """The run's trajectory without the call times (wall-clock, never reproducible)."""
    return pd.read_parquet(folder / "trajectory.parquet").drop(columns="user_time")


def built_in_go_to_goal(folder: Path, robots: int, seed: int) -> pd.DataFrame:
    """The same logic as the examples, run by mimics itself (no ROS).

    On one engine thread, as the bridge runs it (the results do not depend on
    the number of threads; waking a pool every step is slow on a busy machine).
    """
    import numba

    from mimics.records.runner import prepare, run_to_folder

    threads = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        run_to_folder(prepare("line", "go_to_goal", robots=robots, seed=seed,
                              params={"random_yaw": False}), folder, robot_logs="off")
    finally:
        numba.set_num_threads(threads)
    return trajectory(folder)


def assert_same_run(ros_run: pd.DataFrame, reference: pd.DataFrame) -> None:
    assert list(ros_run.columns) == list(reference.columns)
    assert ros_run[["step", "robot", "status"]].equals(reference[["step", "robot", "status"]])
    numbers = ["x", "y", "theta", "v", "w", "v_ref", "heading_ref"]
    np.testing.assert_allclose(ros_run[numbers].to_numpy(), reference[numbers].to_numpy(),
                               rtol=0, atol=1e-9)


def test_rospy_example_drives_five_robots_and_lockstep_repeats_exactly(ros_env, tmp_path):
    node = [SYSTEM_PYTHON, str(EXAMPLES / "go_to_goal_node.py"), "--robots", "5"]
    runs = []
    for name in ("first", "second"):
        folder = tmp_path / name
        bridge, output = with_node(ros_env, node, "line", "--robots", "5", "--seed", "3", *FACING,
                                   "--lockstep", "--out", str(folder), "--robot-logs", "off")
        assert bridge.returncode == 0, bridge.stderr + output
        outcome = summary(folder)
        assert (outcome["status"], outcome["reached_goal"], outcome["collisions"]) == (
            "completed", 5, 0)
        assert outcome["ros"]["mode"] == "lockstep"
        runs.append(trajectory(folder))
    assert runs[0].equals(runs[1])  # bit for bit: lockstep is deterministic
    assert_same_run(runs[0], built_in_go_to_goal(tmp_path / "python", 5, 3))


def test_roscpp_example_drives_five_robots(ros_env, tmp_path):
    require("compiler")
    require("roscpp")
    binary = tmp_path / "go_to_goal_node"
    flags = subprocess.run(["pkg-config", "--cflags", "--libs", "roscpp", "std_msgs",
                            "nav_msgs", "geometry_msgs"], capture_output=True, text=True,
                           check=True).stdout.split()
    build = subprocess.run([shutil.which("g++") or "g++", "-O1", "-o", str(binary),
                            str(EXAMPLES / "go_to_goal_node.cpp"), *flags],
                           capture_output=True, text=True, check=False)
    assert build.returncode == 0, build.stderr
    folder = tmp_path / "cpp"
    bridge, output = with_node(ros_env, [str(binary), "5"], "line", "--robots", "5", *FACING,
                               "--seed", "3", "--out", str(folder), "--robot-logs", "off")
    assert bridge.returncode == 0, bridge.stderr + output
    outcome = summary(folder)
    assert (outcome["status"], outcome["reached_goal"], outcome["collisions"]) == (
        "completed", 5, 0)
    reference = built_in_go_to_goal(tmp_path / "python", 5, 3)
    assert_same_run(trajectory(folder), reference)
    # the same binary as a `ros:` algorithm: mimics starts a master and the node itself
    own = tmp_path / "ros_algorithm"
    done = subprocess.run([sys.executable, "-m", "mimics", "run", "line",
                           f"ros:{binary} {{robots}}", "--robots", "5", "--seed", "3", *FACING,
                           "--out",
                           str(own), "--robot-logs", "off"], capture_output=True, text=True,
                          timeout=120, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert summary(own)["algorithm"] == "ros-go_to_goal_node"
    assert_same_run(trajectory(own), reference)


def test_no_master_is_one_line_naming_ros_master_uri(tmp_path):
    require("ros")
    env = {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{free_port()}"}
    done = mimics_ros(env, "line", "--robots", "1", "--out", str(tmp_path / "run"))
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith("mimics: error: no ROS master at ROS_MASTER_URI=http://127.0.0.1:")
    assert not (tmp_path / "run").exists()


def test_malformed_messages_hold_the_reference_twist_turns_and_silence_times_out(
        ros_env, tmp_path):
    folder = tmp_path / "run"
    node = [SYSTEM_PYTHON, str(NODES / "scripted_node.py"), "--stop-at", "2.0"]
    bridge, output = with_node(ros_env, node, "line", "--robots", "2", "--timeout", "1",
                               "--out", str(folder), "--robot-logs", "off")
    # silence: the lockstep time-out ends the run, with one clear line and status 1
    assert bridge.returncode == 1, bridge.stderr + output
    last = bridge.stderr.strip().splitlines()[-1]
    # one deadline for the step: both robots are named, and the option that sets it
    assert last.startswith("mimics: error: LockstepTimeout in robot 0 at t=2 s: no command for "
                           "t=2 s within 1 s (--timeout) from 2 robots: 0, 1 (on "
                           "/robot_i/cmd or /robot_i/cmd_vel)"), last
    outcome = summary(folder)
    assert outcome["status"] == "error" and "LockstepTimeout" in outcome["error"]
    table = pd.read_parquet(folder / "trajectory.parquet")
    # observations before t = 2 s were answered (steps 1 to 20); the step that
    # timed out is the last one recorded
    assert table["step"].max() == 21

    # robot 0: row s holds the reference that answered step s-1's observation;
    # a malformed answer keeps the previous one
    robot = table[table["robot"] == 0].set_index("step")
    expected = []
    held = (0.0, 0.0)
    for step in range(1, 21):
        answered = step - 1
        if answered not in script.MALFORMED:
            held = (script.reference_speed(answered), script.reference_heading(answered))
        expected.append(held)
    got = robot.loc[1:20, ["v_ref", "heading_ref"]].to_numpy()
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12)
    events = pd.read_parquet(folder / "events.parquet")
    notes = events[(events["kind"] == "user_message") & (events["robot"] == 0)]
    assert len(notes) == len(script.MALFORMED)
    assert all("holding the last reference" in text for text in notes["detail"])
    assert "speed_ref must be a finite number, got nan" in notes["detail"].iloc[0]
    assert "got 4 values" in notes["detail"].iloc[1]
    # the malformed messages answered steps 5 and 8, logged with the step that used them
    assert notes["step"].tolist() == [step + 1 for step in sorted(script.MALFORMED)]

    # robot 1 (cmd_vel): the speed reference is the commanded speed; in steady
    # state the heading loop turns it at the commanded rate
    driven = table[(table["robot"] == 1) & table["step"].between(1, 20)]
    assert (driven["v_ref"] == script.TWIST_SPEED).all()
    np.testing.assert_allclose(driven[driven["time"] >= 1.5]["w"], script.TWIST_RATE,
                               rtol=0.01)


def test_realtime_keeps_wall_clock_pace_and_uses_the_last_command(ros_env, tmp_path):
    folder = tmp_path / "run"
    node = [SYSTEM_PYTHON, str(NODES / "scripted_node.py")]
    bridge, output = with_node(ros_env, node, "line", "--robots", "2", "--realtime",
                               "--time", "1", "--out", str(folder), "--robot-logs", "off")
    assert bridge.returncode == 0, bridge.stderr + output
    outcome = summary(folder)
    assert outcome["status"] == "time_limit" and outcome["ros"]["mode"] == "realtime"
    # never faster than the wall clock (it sleeps until each step's time)
    assert outcome["wall_time"] >= 0.95 * outcome["sim_time"]
    table = pd.read_parquet(folder / "trajectory.parquet")
    last = table[(table["robot"] == 1) & (table["step"] == table["step"].max())]
    assert float(last["v_ref"].iloc[0]) == pytest.approx(script.TWIST_SPEED)
    assert float(last["v"].iloc[0]) > 0.5 * script.TWIST_SPEED  # it did drive


def test_params_shape_the_scenario_and_the_view_and_video_come_as_for_run(ros_env, tmp_path):
    """``--param`` reaches the scenario as in ``mimics run`` (spacing and distance
    change the start and the goals), ``--view`` without a display says so and
    runs on, ``--video`` writes the run's replay."""
    import imageio

    from mimics.interfaces.live_view import no_display_notice
    from mimics.records.runner import prepare, run_to_folder

    params = ("--param", "spacing=2.5", "--param", "distance=4.0", *FACING)
    node = [SYSTEM_PYTHON, str(EXAMPLES / "go_to_goal_node.py"), "--robots", "3"]
    folder, video = tmp_path / "ros", tmp_path / "run.mp4"
    bridge, output = with_node(ros_env, node, "line", "--robots", "3", *params, "--seed", "2",
                               "--out", str(folder), "--robot-logs", "off",
                               "--view", "1s", "--video", str(video))
    assert bridge.returncode == 0, bridge.stderr + output
    assert no_display_notice("1s") in bridge.stderr
    outcome = summary(folder)
    assert (outcome["status"], outcome["reached_goal"]) == ("completed", 3)
    ros_run = trajectory(folder)
    start = ros_run[ros_run["step"] == ros_run["step"].min()].sort_values("robot")
    np.testing.assert_allclose(start["y"], [2.5, 5.0, 7.5], atol=1e-9)  # spacing 2.5
    reference = prepare("line", "go_to_goal", robots=3, seed=2,
                        params={"spacing": 2.5, "distance": 4.0, "random_yaw": False})
    run_to_folder(reference, tmp_path / "python", robot_logs="off")
    assert_same_run(ros_run, trajectory(tmp_path / "python"))
    reader = imageio.get_reader(video, format="FFMPEG")
    first, second = reader.get_data(0), reader.get_data(1)
    reader.close()
    assert first.ndim == 3 and first.shape == second.shape


def test_bad_params_exit_2_naming_the_option(ros_env, tmp_path):
    done = mimics_ros(ros_env, "line", "--param", "spacing", "--out", str(tmp_path / "run"))
    assert done.returncode == 2
    assert "--param 'spacing': expected NAME=VALUE" in done.stderr
    done = mimics_ros(ros_env, "line", "--view", "sometimes", "--out", str(tmp_path / "run"))
    assert done.returncode == 2 and "--view: expected one of" in done.stderr
    assert not (tmp_path / "run").exists()
