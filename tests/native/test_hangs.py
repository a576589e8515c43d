"""A compiled step that never returns (``for(;;);``) is cut at the wall limit, in the Python
API and on the command line, with nothing left running."""

from __future__ import annotations

import subprocess
import sys
import threading
from pathlib import Path

import mimics
from mimics.engine.state import Status
from mimics.engine.user_code.watchdog import GRACE, RETRY
from tests.engine.user_code.test_wall_limit import threads_left
from tests.native.conftest import ALGORITHMS
from tests.processes import left_running, marked_environment

#: A bound that only a run the watchdog failed to stop exceeds (not a speed test).
NEVER = 1.0 + GRACE + 20 * RETRY


def test_a_c_step_that_never_returns_is_cut_and_the_run_recorded(tmp_path: Path) -> None:
    threads = set(threading.enumerate())
    result = mimics.simulate("line", str(ALGORITHMS / "spin.c"), robots=3, wall_limit=1.0,
                             out=tmp_path / "run")
    assert (result.status, result.error) == (
        "wall_limit", "robot 1: mimics_step in spin.c did not return within the wall limit of "
                      "1 s; stopped at step 3 (t=0.3 s)")
    assert 1.0 <= result.wall_time < NEVER
    assert result.final_status.tolist() == [Status.ACTIVE, Status.ERROR, Status.ACTIVE]
    assert threads_left(threads) == set()
    run = mimics.load_run(tmp_path / "run")
    assert run.complete and int(run.trajectory["step"].max()) == 3
    assert run.read_events(kinds=["exception"])["detail"].tolist() == [
        "Exception: StepTimeout: mimics_step in spin.c did not return within the wall limit "
        "of 1 s"]
    # the process goes on normally: the same build runs again, to its end this time
    again = mimics.simulate("line", str(ALGORITHMS / "spin.c"), robots=1, time=1.0)
    assert again.status == "time_limit"


def test_a_cpp_team_step_that_never_returns_is_cut(tmp_path: Path) -> None:
    result = mimics.simulate("line", str(ALGORITHMS / "spin_team.cpp"), robots=4,
                             wall_limit=1.0)
    assert result.error == ("the team algorithm: mimics_team_step in spin_team.cpp did not "
                            "return within the wall limit of 1 s; stopped at step 1 (t=0.1 s)")
    assert (result.final_status == Status.ERROR).all()


def test_the_command_exits_1_naming_robot_and_step_and_leaves_nothing_running(
        tmp_path: Path) -> None:
    env, marker = marked_environment()
    done = subprocess.run(
        [sys.executable, "-m", "mimics", "run", "line", str(ALGORITHMS / "spin.c"), "--robots",
         "3", "--wall-limit", "1", "--out", str(tmp_path / "run")],
        capture_output=True, text=True, env=env, timeout=300, check=False)
    assert done.returncode == 1, done.stderr
    assert ("error: robot 1: mimics_step in spin.c did not return within the wall limit of 1 s; "
            "stopped at step 3 (t=0.3 s)\n") in done.stdout
    assert "Traceback" not in done.stdout + done.stderr
    assert left_running(marker) == []  # neither the command nor its child process
    report = subprocess.run([sys.executable, "-m", "mimics", "report", str(tmp_path / "run")],
                            capture_output=True, text=True, check=False)
    assert report.returncode == 0 and "wall_limit" in report.stdout
