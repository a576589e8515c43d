"""What ROS tools look for, against a real ``rosmaster``: ``/use_sim_time``, the
``/mimics`` parameters, live markers and the pause/step/resume/reset services."""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mimics.scenarios.line import scenario as line
from tests.interfaces.ros.helpers import NODES, SYSTEM_PYTHON, with_node

FACING = ("--param", "random_yaw=false")
DT_NS = 100_000_000  # the line scenario's step, 0.1 s
CUBE, CYLINDER, TEXT_VIEW_FACING = 1, 3, 9  # visualization_msgs/Marker's numbering


def node(mode: str, *args: str) -> list[str]:
    return [SYSTEM_PYTHON, str(NODES / "control_node.py"), "--mode", mode, *args]


def last_json_line(output: str) -> dict:
    return json.loads([line for line in output.splitlines() if line.startswith("{")][-1])


def summary(folder: Path) -> dict:
    return json.loads((folder / "summary.json").read_text())


def test_sim_time_parameters_and_markers(ros_env, tmp_path):
    folder = tmp_path / "run"
    bridge, output = with_node(ros_env, node("observe", "--robots", "3"), "line", "--robots",
                               "3", "--time", "0.5", *FACING, "--out", str(folder))
    assert bridge.returncode == 0, bridge.stderr
    found = last_json_line(output)
    assert found["sim_time_at_first_clock"] is True  # set before the first /clock
    # and put back as it was (unset) at the end, with the /mimics tree removed
    left = subprocess.run(
        [SYSTEM_PYTHON, "-c", "import json, rosgraph; m = rosgraph.Master('/check'); "
         "print(json.dumps([m.hasParam('/use_sim_time'), m.hasParam('/mimics')]))"],
        env=ros_env, capture_output=True, text=True, check=True, timeout=60)
    assert json.loads(left.stdout) == [False, False]
    params = found["params"]
    scenario = line(robots=3, random_yaw=False)
    assert (params["robots"], params["scenario"], params["dt"], params["lockstep"]) == (
        3, "line", 0.1, True)
    for robot in range(3):
        kind = scenario.robot_type(robot)
        entry = params[f"robot_{robot}"]
        assert entry["type"] == kind.name
        assert entry["footprint"] == [kind.length, kind.width]
        assert (entry["max_speed"], entry["max_turn_rate"]) == (kind.kv, kind.kw)
        # the line's robots carry a 270-beam laser over 3/2 pi, 30 m (robot_types.py)
        assert entry["ranger"]["beams"] == kind.ranger.beams == 270
        assert math.isclose(entry["ranger"]["fov"], 1.5 * math.pi)
        assert entry["ranger"]["range"] == 30.0
    # one MarkerArray per step, each robot's footprint and id at its recorded pose
    rows = pd.read_parquet(folder / "trajectory.parquet")
    steps = sorted(rows["step"].unique())
    by_stamp = {stamp: markers for stamp, markers in found["markers"]}
    assert sorted(by_stamp) == [step * DT_NS for step in steps]
    for step in steps:
        markers = by_stamp[step * DT_NS]
        expected = rows[rows["step"] == step].sort_values("robot")
        for namespace, kind in (("footprint", CUBE), ("id", TEXT_VIEW_FACING)):
            drawn = sorted(m for m in markers if m[0] == namespace)
            assert [m[1] for m in drawn] == expected["robot"].tolist()
            assert all(m[2] == "map" and m[5] == kind for m in drawn)
            np.testing.assert_array_equal([[m[3], m[4]] for m in drawn],
                                          expected[["x", "y"]].to_numpy())
        assert [m[6] for m in markers if m[0] == "id"] == ["0", "1", "2"]
        goals = sorted(m for m in markers if m[0] == "goal")
        assert [(m[3], m[4]) for m in goals] == [tuple(g) for g in scenario.goals.tolist()]
        assert all(m[5] == CYLINDER for m in goals)


@pytest.mark.parametrize("mode", ["--lockstep", "--realtime"])
def test_pause_holds_time_step_advances_one_resume_goes_on_reset_restarts(ros_env, tmp_path,
                                                                            mode):
    folder = tmp_path / "run"
    # lockstep: long enough for the pause to land before the end on a loaded machine (the
    # steps go as fast as the node answers); realtime: 3 s of wall time after the reset
    seconds = 60 if mode == "--lockstep" else 3
    bridge, output = with_node(ros_env, node("control", "--robots", "2", "--at", "0.5",
                                             "--reset-at", "1.0"),
                               "line", "--robots", "2", "--time", str(seconds), mode, *FACING,
                               "--out", str(folder))
    assert bridge.returncode == 0, bridge.stderr
    report = last_json_line(output)
    assert report["refused_step"][0] is False  # not paused: no step
    assert report["pause"][0] is True
    paused = report["last_clock_paused"]
    assert paused >= 5 * DT_NS
    assert f"t={paused / 1e9:g} s" in report["pause"][1]
    assert report["clocks_while_paused"] == []  # simulated time stood still
    assert report["step"][0] is True
    assert report["clocks_after_step"] == [paused + DT_NS]  # exactly one step
    assert report["resume"][0] is True
    assert report["reset"][0] is True
    # the clock went back to the start; the run started again in a new folder
    assert report["clocks_after_reset"][0] == 0
    again = tmp_path / "run-reset-1"
    assert str(again) in report["reset"][1]
    assert str(again) in bridge.stdout.replace("\n", "")  # Rich wraps long paths
    first, second = summary(folder), summary(again)
    assert first["status"] == "stopped"
    assert second["status"] == "time_limit" and second["steps"] == seconds * 10
    if mode == "--realtime":
        return  # realtime takes the latest command: not a repeatable run
    # the same start state and seed: the steps both runs made are the same
    old = pd.read_parquet(folder / "trajectory.parquet").drop(columns="user_time")
    new = pd.read_parquet(again / "trajectory.parquet").drop(columns="user_time")
    assert old["step"].max() >= paused // DT_NS + 1
    new = new[new["step"] <= old["step"].max()].reset_index(drop=True)
    pd.testing.assert_frame_equal(old, new)
