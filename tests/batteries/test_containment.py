"""Each submission is contained (issue 54): loaded only in a worker, under the time-out;
and it cannot change the world or see its classmates.

One battery of hand-written submissions on two robots: broken files of each kind
cost only their own runs, named with their line; each known way into the world is
tried from inside ``step`` and must either fail or leave the run bit for bit the run
of the same step without the attack (the same digest, the independent truth).
"""

from __future__ import annotations

import contextlib
import io
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from mimics.batteries.driver import run_battery
from mimics.batteries.grading import code_hash, flag_copies
from mimics.batteries.report import runs_table
from mimics.batteries.spec import spec_from_dict

HONEST = '''import math

def step(robot):
    x, y, _ = robot.pose
    gx, gy = robot.goal
    speed, heading = 1.0, math.atan2(gy - y, gx - x)
    {attack}
    return speed, heading
'''

ATTACKS = {
    "private_attributes": '''for holder in (robot, robot.scan):
        for name in holder.__slots__:
            value = getattr(holder, name, None)
            for inner in (getattr(value, "state", None), getattr(value, "_sim", None)):
                if inner is not None:
                    inner.state.pose[robot.id, :2] = robot.goal
        getattr(robot, "_mirror").pose[robot.id, :2] = robot.goal''',
    "gc_objects": '''import gc
    try:
        for thing in gc.get_objects():
            if type(thing).__name__ == "WorldState":
                thing.pose[:, :2] = thing.goal
    except PermissionError:
        robot.memory["refused"] = True''',
    "gc_referrers": '''import gc
    try:
        for thing in gc.get_referrers(robot):
            robot.memory["seen"] = thing
    except PermissionError:
        pass''',
    "frames": '''import sys
    try:
        frame = sys._getframe().f_back
        while frame is not None:
            sim = frame.f_locals.get("sim")
            if sim is not None:
                sim.state.pose[robot.id, :2] = robot.goal
            frame = frame.f_back
    except PermissionError:
        pass''',
    "traceback_frames": '''try:
        raise ValueError
    except ValueError as exc:
        try:
            frame = exc.__traceback__.tb_frame.f_back
            sim = frame.f_locals.get("sim")
            sim.state.pose[robot.id, :2] = robot.goal
        except (PermissionError, AttributeError):
            pass''',
    "link_frame": '''try:
        hub = robot._link.gi_frame.f_locals["self"]
        hub._sim.state.pose[robot.id, :2] = robot.goal
    except PermissionError:
        pass''',
    "arrays": '''for row in (robot.true_pose, robot.pose, robot.odometry, robot.velocity):
        for target in (row, row.base[robot.id]):  # its own row: the others read theirs
            try:
                target.flags.writeable = True
                target[...] = 0.0
            except ValueError:
                pass''',
    "instance_dict": '''try:
        robot.__dict__["_sim"].state.pose[robot.id, :2] = robot.goal
    except AttributeError:
        pass''',
    "closures": '''for value in vars(type(robot)).values():
        getter = getattr(value, "fget", None)
        for cell in getattr(getter, "__closure__", None) or ():
            state = getattr(cell.cell_contents, "state", None)
            if state is not None:
                state.pose[robot.id, :2] = robot.goal''',
    "classmates": '''import os
    folder = os.path.dirname(os.path.abspath(__file__))
    robot.memory["classmates"] = [n for n in os.listdir(folder) if n != os.path.basename(__file__)]
    if robot.memory["classmates"]:
        raise RuntimeError("saw " + ", ".join(robot.memory["classmates"]))''',
}

BROKEN = {
    "syntax_error": "def step(robot)\n    return 1.0, 0.0\n",
    "failed_import": "import no_such_module_anywhere\n\ndef step(robot):\n    return 1.0, 0.0\n",
    "raises_at_import": "x = 1\nraise RuntimeError('at import')\n",
    "loops_at_import": "import time\nwhile True:\n    time.sleep(0.01)\n",
    "exits_at_import": "import sys\nprint('student output')\nsys.exit(3)\n",
}

TIMEOUT = 6.0


@pytest.fixture(scope="module")
def battery(tmp_path_factory: pytest.TempPathFactory) -> pd.DataFrame:
    folder = tmp_path_factory.mktemp("class")
    submissions = folder / "submissions"
    submissions.mkdir()
    files = {"honest": HONEST.format(attack="pass"),
             "honest_copy": "# my own work!\n" + HONEST.format(attack="pass") + "\n\n",
             **{name: HONEST.format(attack=code) for name, code in ATTACKS.items()},
             **BROKEN}
    for name, code in files.items():
        (submissions / f"{name}.py").write_text(code)
    spec = spec_from_dict({
        "battery": {"algorithms": [str(submissions / f"{n}.py") for n in files], "seeds": 1,
                    "time": 1.0, "timeout": TIMEOUT, "policy": "abort"},
        "scenarios": [{"name": "line", "robots": 2}]})  # nothing imported: no print here
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        run_battery(spec, folder / "b", workers=2, progress=False)
    assert "student output" not in printed.getvalue()
    return runs_table(folder / "b").set_index("algorithm")


@pytest.mark.parametrize("name,state,where", [
    ("syntax_error", "error", "line 1: syntax error"),
    ("failed_import", "error", "line 1: importing it raised ModuleNotFoundError"),
    ("raises_at_import", "error", "line 2: importing it raised RuntimeError: at import"),
    ("loops_at_import", "timeout", "line 3: importing it did not finish within"),
    ("exits_at_import", "error", "line 3: importing it called sys.exit(3)"),
])
def test_a_broken_file_costs_only_its_own_runs(battery: pd.DataFrame, name: str, state: str,
                                                where: str) -> None:
    run = battery.loc[name]
    assert run["state"] == state
    assert f"submissions/{name}.py" in run["error"] and where in run["error"], run["error"]
    assert battery.loc["honest", "state"] == "done"  # the battery went on with the others


@pytest.mark.parametrize("attack", sorted(set(ATTACKS) - {"classmates"}))
def test_no_way_in_changes_the_world(battery: pd.DataFrame, attack: str) -> None:
    run = battery.loc[attack]
    assert run["state"] == "done", run["error"]
    assert run["digest"] == battery.loc["honest", "digest"]  # the very same trajectories
    assert run["reached_goal"] == battery.loc["honest", "reached_goal"]


def test_a_submission_sees_no_classmate_file(battery: pd.DataFrame) -> None:
    assert battery.loc["classmates", "state"] == "done", battery.loc["classmates", "error"]


def test_identical_submissions_are_flagged(battery: pd.DataFrame) -> None:
    runs = battery.reset_index()
    table = pd.DataFrame({"mark": [1.0] * 3}, index=pd.Index(
        ["honest", "honest_copy", "syntax_error"], name="student"))
    flagged = flag_copies(table, runs)["copy_of"].to_dict()
    assert "honest_copy" in flagged["honest"] and "honest" in flagged["honest_copy"]
    assert flagged["syntax_error"] == ""


def test_the_code_hash_ignores_comments_and_spacing(tmp_path: Path) -> None:
    a, b, c = tmp_path / "a.py", tmp_path / "b.py", tmp_path / "c.py"
    a.write_text("def step(robot):\n    return 1.0, 0.0\n")
    b.write_text("# mine\n\ndef step( robot ):  # really\n    return 1.0,0.0\n\n")
    c.write_text("def step(robot):\n    return 1.0, 0.5\n")
    assert code_hash(a) == code_hash(b) != code_hash(c)


def test_mimics_run_stops_an_endless_loop_at_import(tmp_path: Path) -> None:
    looping = tmp_path / "loops.py"
    looping.write_text("while True:\n    pass\n")
    done = subprocess.run([sys.executable, "-m", "mimics", "run", "line", str(looping),
                           "--robots", "1", "--wall-limit", "2"], capture_output=True,
                          text=True, timeout=60)
    assert done.returncode == 2, done.stderr
    assert "loops.py" in done.stderr and "did not finish within 2 s" in done.stderr
