"""``ros:`` algorithms: a ROS controller node in batteries and in ``mimics run``.

Each run starts its process's private master and the node itself; nothing
here uses a shared master. The reference is mimics' own ``go_to_goal``,
whose logic the example node repeats: the ROS runs must equal it bit for bit.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pandas as pd
import pytest

from tests.interfaces.ros.helpers import EXAMPLES
from tests.system_packages import require

NODE = "go_to_goal_node.py"


def trajectory(folder: Path) -> pd.DataFrame:
    """The run's trajectory without the call times (wall-clock, never reproducible)."""
    return pd.read_parquet(folder / "trajectory.parquet").drop(columns="user_time")


def mimics(*args: str, env: dict[str, str] | None = None, cwd: Path | None = None,
           timeout: float = 300) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "mimics", *args], capture_output=True,
                          text=True, env=env, cwd=cwd, timeout=timeout, check=False)


def processes_marked(mark: str) -> list[str]:
    """Command lines of live processes whose environment holds ``mark`` (Linux /proc)."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            if mark.encode() in (entry / "environ").read_bytes():
                found.append((entry / "cmdline").read_bytes().replace(b"\0", b" ").decode())
        except OSError:  # gone meanwhile, or not ours to read
            continue
    return found


@pytest.fixture
def node_folder(tmp_path: Path) -> Path:
    """A folder with a copy of the example node, as a user's project would hold it."""
    require("ros")
    shutil.copy(EXAMPLES / NODE, tmp_path / NODE)
    return tmp_path


def test_battery_of_ros_runs_equals_the_built_in_runs_and_leaves_no_process(
        node_folder: Path) -> None:
    battery = node_folder / "battery.toml"
    battery.write_text(f'''[battery]
algorithms = ["ros:{NODE} --robots {{robots}}", "go_to_goal"]
seeds = [1, 2]

[[scenarios]]
name = "line"
robots = 5
noise = "off"  # both steer by the positioning sensor: exact, so the same runs
random_yaw = false  # facing their goals, the node and go_to_goal turn alike
''')
    mark = f"MIMICS_TEST_MARK_{uuid.uuid4().hex}"
    env = {**os.environ, mark: "1"}
    done = mimics("battery", "run", str(battery), "--out", str(node_folder / "out"),
                  "--workers", "2", env=env)
    assert done.returncode == 0, done.stdout + done.stderr

    runs = {p.name: p for p in (node_folder / "out" / "runs").iterdir()}
    assert sorted(runs) == ["00001-ros-go_to_goal_node-line-robots=5-noise=off-random_yaw=False-s1",
                            "00002-ros-go_to_goal_node-line-robots=5-noise=off-random_yaw=False-s2",
                            "00003-go_to_goal-line-robots=5-noise=off-random_yaw=False-s1",
                            "00004-go_to_goal-line-robots=5-noise=off-random_yaw=False-s2"]
    for seed, ros_run, own_run in ((1, "00001", "00003"), (2, "00002", "00004")):
        ros_folder = next(p for name, p in runs.items() if name.startswith(ros_run))
        own_folder = next(p for name, p in runs.items() if name.startswith(own_run))
        ros_outcome = json.loads((ros_folder / "battery.json").read_text())
        assert ros_outcome["state"] == "done", ros_outcome
        own_outcome = json.loads((own_folder / "battery.json").read_text())
        # the line's random headings (from the seed) are the same for both algorithms
        assert ros_outcome["counts"] == own_outcome["counts"]
        summary = json.loads((ros_folder / "summary.json").read_text())
        assert summary["algorithm"] == "ros-go_to_goal_node"
        assert summary["seed"] == seed
        pd.testing.assert_frame_equal(trajectory(ros_folder), trajectory(own_folder),
                                      check_exact=True)
    # the workers have stopped their nodes and masters, or the kernel has killed them
    assert processes_marked(mark) == []


def test_mimics_run_takes_a_ros_node_relative_to_the_current_folder(node_folder: Path) -> None:
    done = mimics("run", "line", f"ros:{NODE} --robots {{robots}}", "--robots", "3", "--seed",
                  "4", "--param", "random_yaw=false", "--out", "ros_run", cwd=node_folder)
    assert done.returncode == 0, done.stdout + done.stderr
    summary = json.loads((node_folder / "ros_run" / "summary.json").read_text())
    assert (summary["algorithm"], summary["robots"], summary["reached_goal"]) == (
        "ros-go_to_goal_node", 3, 3)


def test_a_missing_node_program_is_named_with_status_2(node_folder: Path) -> None:
    done = mimics("run", "line", "ros:no_such_node.py --robots 5", cwd=node_folder)
    assert done.returncode == 2
    assert "no program" in done.stderr and "no_such_node.py" in done.stderr
    assert "Traceback" not in done.stderr

    battery = node_folder / "battery.toml"
    battery.write_text('[battery]\nalgorithms = ["ros:no_such_node.py"]\n\n'
                       '[[scenarios]]\nname = "line"\n')
    done = mimics("battery", "run", str(battery), "--out", str(node_folder / "out"))
    assert done.returncode == 2
    assert "battery.toml" in done.stderr and "algorithms" in done.stderr
    assert "no_such_node.py" in done.stderr


def test_an_unknown_kind_of_algorithm_is_named_with_status_2(tmp_path: Path) -> None:
    done = mimics("run", "line", "rso:node.py", cwd=tmp_path)
    assert done.returncode == 2
    assert "unknown kind 'rso:'" in done.stderr and "ros:" in done.stderr


def test_a_node_that_exits_before_connecting_ends_the_run_with_its_status(
        node_folder: Path) -> None:
    quitter = node_folder / "quitter.py"
    quitter.write_text("import sys\nsys.exit(3)\n")
    done = mimics("run", "line", f"ros:{quitter.name}", "--robots", "2", cwd=node_folder,
                  timeout=120)
    assert done.returncode != 0
    assert "exited with status 3 before it connected" in done.stdout + done.stderr


def test_killing_mimics_mid_run_kills_its_node_and_master(node_folder: Path) -> None:
    mark = f"MIMICS_TEST_MARK_{uuid.uuid4().hex}"
    run = subprocess.Popen([sys.executable, "-m", "mimics", "run", "line",
                            f"ros:{NODE} --robots {{robots}}", "--robots", "3", "--time", "1e4",
                            "--out", "killed"], cwd=node_folder, env={**os.environ, mark: "1"},
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 120
        node = str(node_folder / NODE)  # as the node's command line has it
        while not any(node in line for line in processes_marked(mark)):  # the run is under way
            assert run.poll() is None and time.monotonic() < deadline
            time.sleep(0.2)
        assert any("rosmaster" in line for line in processes_marked(mark))
    finally:
        run.kill()  # SIGKILL: no cleanup of its own
        run.wait()
    deadline = time.monotonic() + 10
    while processes_marked(mark) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert processes_marked(mark) == []


def test_battery_new_writes_a_ros_algorithm_with_its_program_made_absolute(
        node_folder: Path) -> None:
    done = mimics("battery", "new", "--algorithm", f"ros:{NODE} --robots {{robots}}",
                  "--scenario", "line", "--seeds", "2", "--no-input", "--output",
                  "sub/battery.toml", cwd=node_folder)
    assert done.returncode == 0, done.stdout + done.stderr
    import tomllib

    written = tomllib.loads((node_folder / "sub" / "battery.toml").read_text())
    assert written["battery"]["algorithms"] == [
        f"ros:{node_folder / NODE} --robots {{robots}}"]


def test_a_process_already_on_another_master_is_told_so(node_folder: Path) -> None:
    """rospy joins one master per process: a ros: run after `mimics ros`'s node in the
    same process would wait for nodes it cannot see; it says so instead."""
    script = node_folder / "two_masters.py"
    script.write_text(f"""
import sys
from mimics.interfaces.ros import private_master, system_ros
from mimics.records.runner import prepare
from mimics.world.errors import MimicsError

system_ros.require_ros()
import rospy

uri = private_master.private_master()  # stands for a master of the user's
rospy.init_node("someone_else", disable_signals=True)
private_master.stop_private_master()  # this process keeps its node of that master
try:
    prepare("line", "ros:{NODE} --robots {{robots}}", robots=2).run()
except MimicsError as exc:
    print("refused:", exc)
    sys.exit(0)
sys.exit("ran against a master it cannot share")
""")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True,
                          cwd=node_folder, timeout=120, check=False)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "already a ROS node of the master" in done.stdout
