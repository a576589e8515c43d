"""SIGINT (Ctrl-C) and SIGTERM (what roslaunch sends) end a ``mimics ros`` run cleanly,
against a real ``rosmaster``: the run ends at a step boundary with status
``interrupted``, its summary and records are written (``mimics report`` reads
them), the parameter server holds nothing mimics set, and the master lists
none of its topics, services or its node.
"""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time

import pandas as pd
import pytest

from tests.interfaces.ros.helpers import NODES, SYSTEM_PYTHON


def master(env: dict[str, str]):  # rosgraph's Master, from the system's ROS
    from mimics.interfaces.ros.system_ros import require_ros

    require_ros()
    import rosgraph

    return rosgraph.Master("/stopping_test", master_uri=env["ROS_MASTER_URI"])


def start_mimics(env: dict[str, str], *args: str) -> subprocess.Popen[str]:
    return subprocess.Popen([sys.executable, "-m", "mimics", "ros", *args], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def wait_until_running(env: dict[str, str], process: subprocess.Popen[str]) -> None:
    """Until ``/use_sim_time`` is set: just before the first ``/clock``."""
    server = master(env)
    deadline = time.monotonic() + 90
    while not server.hasParam("/use_sim_time"):
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline, "the run did not start"
        time.sleep(0.05)


def nodes_of(server) -> set[str]:
    publishers, subscribers, services = server.getSystemState()
    return {node for _, nodes in (*publishers, *subscribers, *services) for node in nodes}


@pytest.mark.parametrize(("signum", "style"), [(signal.SIGINT, "realtime"),
                                                (signal.SIGTERM, "lockstep")])
def test_a_signal_ends_the_run_with_its_summary_and_a_clean_master(ros_env, tmp_path,
                                                                   signum, style):
    folder = tmp_path / "run"
    node = None
    if style == "lockstep":  # a node answering every step: the run waits in the inbox
        node = subprocess.Popen([SYSTEM_PYTHON, str(NODES / "stage_styles_node.py"),
                                 "--style", "late-scan", "--late", "0", "--speed", "0.05"],
                                env=ros_env, stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True)
        # slowly ahead (to goals 20 m away): no deadlock, no arrival before the signal
        args = ["--names", "stage", "--lockstep", "--param", "random_yaw=false"]
    else:  # stage names' default: realtime, no node needed
        args = ["--names", "stage", "--startup-grace", "0.2"]
    process = start_mimics(ros_env, "line", "--robots", "2", "--time", "10000", "--out",
                           str(folder), *args)
    try:
        wait_until_running(ros_env, process)
        time.sleep(1.0)  # some steps
        process.send_signal(signum)
        sent = time.monotonic()
        out, err = process.communicate(timeout=30)
        took = time.monotonic() - sent
    finally:
        if process.poll() is None:
            process.kill()
        if node is not None:
            node.send_signal(signal.SIGINT)
            node.communicate(timeout=30)
    print(f"{signal.Signals(signum).name}: the process ended {took:.2f} s after the signal")
    assert process.returncode == 128 + signum, out + err
    summary = json.loads((folder / "summary.json").read_text())
    assert summary["status"] == "interrupted"
    assert "interrupted" in out  # the summary printed
    steps = pd.read_parquet(folder / "trajectory.parquet")["step"]
    assert steps.max() == summary["steps"] > 0  # the records end at the last step
    report = subprocess.run([sys.executable, "-m", "mimics", "report", str(folder)],
                            capture_output=True, text=True, timeout=60, check=False)
    assert report.returncode == 0, report.stderr
    assert "interrupted" in report.stdout and "incomplete" not in report.stdout
    server = master(ros_env)
    names = server.getParamNames()
    assert not [name for name in names if name.startswith("/mimics")], names
    assert "/use_sim_time" not in names  # it was unset before the run: unset again
    assert "/stageros" not in nodes_of(server)


def test_ros_arguments_that_are_not_remaps_are_refused():
    done = subprocess.run([sys.executable, "-m", "mimics", "ros", "line", "extra"],
                          capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 2
    assert "'extra'" in done.stderr and "NAME:=VALUE" in done.stderr
