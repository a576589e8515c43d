"""SIGINT (Ctrl-C) and SIGTERM (what ``ros2 launch`` sends) end a ``mimics ros2`` run
cleanly, on loopback: the run ends at a step boundary with status ``interrupted``, its
summary is printed and written, the records end at the last step, and the process exits
as a shell reports a process that signal ended (128 + its number)."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from tests.interfaces.ros2.controller import end_all, wait_until_under_way
from tests.interfaces.ros2.loopback import dds_environment, next_domain

LIMIT = 120.0  # s: a run that has not ended by then has hung


@pytest.mark.parametrize(("signum", "mode"), [(signal.SIGINT, "--realtime"),
                                               (signal.SIGTERM, "--lockstep")])
def test_a_signal_ends_the_run_at_a_step_boundary_with_its_summary(
        tmp_path: Path, signum: signal.Signals, mode: str) -> None:
    domain, folder, mark = next_domain(), tmp_path / "run", tmp_path / "under-way"
    env = dds_environment(domain)
    # the controller marks the run under way after 30 answers (15 steps of 2 robots); the
    # goals 200 m away keep the robots driving long after that
    node = subprocess.Popen([sys.executable, "-m", "tests.interfaces.ros2.controller", "2",
                             str(mark)], env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL)
    run = subprocess.Popen([sys.executable, "-m", "mimics", "ros2", "line", "--robots", "2",
                            "--param", "distance=200", "--time", "10000", "--out", str(folder),
                            "--startup-grace", "0.5", mode], env=env, stdout=subprocess.PIPE,
                           stderr=subprocess.PIPE, text=True)
    try:
        wait_until_under_way(mark, run, LIMIT)
        run.send_signal(signum)
        out, err = run.communicate(timeout=LIMIT)
    finally:
        end_all(node, run)
    assert run.returncode == 128 + signum, out + err
    summary = json.loads((folder / "summary.json").read_text())
    assert (summary["status"], summary["reached_goal"]) == ("interrupted", 0), summary
    assert "interrupted" in out  # the summary printed
    steps = pd.read_parquet(folder / "trajectory.parquet")["step"]
    assert steps.max() == summary["steps"] >= 15  # the records end at the last step
    assert summary["ros2"]["domain"] == domain
