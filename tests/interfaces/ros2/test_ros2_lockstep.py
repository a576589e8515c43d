"""Lockstep over DDS: a ROS 2 controller (Cyclone Python, the test's own types, its own
process) drives ``line``'s robots home; the same seed and controller give one
digest; a controller killed mid-run ends the run within its time-out, recorded."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

from mimics.records.run_folder import load_run
from tests.interfaces.ros2.controller import end_all, wait_until_under_way
from tests.interfaces.ros2.loopback import dds_environment, next_domain

ROBOTS = 2
LIMIT = 120.0  # s: a run that has not ended by then has hung


def _controller(domain: int, *mark: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, "-m", "tests.interfaces.ros2.controller",
                             str(ROBOTS), *mark], env=dds_environment(domain),
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)


def _mimics(domain: int, folder: Path, *arguments: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, "-m", "mimics", "ros2", "line", "--robots",
                             str(ROBOTS), "--out", str(folder), "--strict-lockstep",
                             "--startup-grace", "0.5", *arguments],
                            env=dds_environment(domain), stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)


def _drive(folder: Path) -> str:
    """One lockstep run of the controller; returns the run's trajectory digest."""
    domain = next_domain()
    controller = _controller(domain)
    try:
        run = _mimics(domain, folder, "--timeout", "30")
        _, errors = run.communicate(timeout=LIMIT)
        assert run.returncode == 0, errors
    finally:
        controller.kill()
        controller.communicate()
    summary = load_run(folder).summary
    assert summary["reached_goal"] == ROBOTS, summary
    assert summary["algorithm"] == "ros2"
    return str(summary["trajectory_digest"])


def test_the_controller_drives_every_robot_home_and_runs_repeat(tmp_path: Path) -> None:
    first = _drive(tmp_path / "first")
    second = _drive(tmp_path / "second")
    assert first == second


def test_a_killed_controller_ends_the_run_at_its_timeout(tmp_path: Path) -> None:
    domain, folder, mark = next_domain(), tmp_path / "run", tmp_path / "under-way"
    controller = _controller(domain, str(mark))
    run = _mimics(domain, folder, "--timeout", "2", "--time", "60")
    try:
        # mid-run: the controller has answered 30 commands (15 steps)
        wait_until_under_way(mark, run, LIMIT)
        os.kill(controller.pid, signal.SIGKILL)
        controller.communicate()
        _, errors = run.communicate(timeout=LIMIT)
    finally:
        end_all(controller, run)
    assert run.returncode == 1, errors
    assert "LockstepTimeout" in errors and "within 2 s (--timeout)" in errors
    record = load_run(folder)
    assert record.summary["status"] == "error"
    assert 1.0 < record.trajectory.time.max() < 60.0
