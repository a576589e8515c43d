"""Faults in user code, in real worker processes: each recorded, the battery goes on."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time
from pathlib import Path

from mimics.batteries import run_battery, runs_table
from mimics.batteries.driver import rerun_failed
from mimics.batteries.status import battery_status
from mimics.engine.user_code import shown_path
from tests.batteries.helpers import fault, write_battery
from tests.processes import left_running, marked_environment

FAULTY = ["raise_at_7", "loop_forever", "exit_3", "segfault", "nan"]


def test_every_fault_is_recorded_and_the_other_runs_complete(tmp_path: Path) -> None:
    path = write_battery(tmp_path / "faults.toml",
                         ["go_to_goal", *(fault(f) for f in FAULTY), fault("slow_go")],
                         seeds=1, time=1.0, timeout=2.0)
    start = time.monotonic()
    result = run_battery(path, tmp_path / "b", workers=2, progress=False)
    elapsed = time.monotonic() - start
    table = runs_table(tmp_path / "b").set_index("algorithm")
    states = table["state"].to_dict()
    assert states == {"go_to_goal": "done", "raise_at_7": "error", "loop_forever": "timeout",
                      "exit_3": "crashed", "segfault": "crashed", "nan": "error",
                      "slow_go": "done"}
    assert result.counts == {"done": 2, "error": 2, "timeout": 1, "crashed": 2}
    error = table["error"]
    # the error names the file and line of the user's code and shows that line
    assert error["raise_at_7"] == (f"ValueError in robot 0 at t=0.6 s, "
                                   f"{shown_path(fault('raise_at_7'))}:7: boom at step 7\n"
                                   f'    raise ValueError("boom at step 7")')
    assert 'raise ValueError("boom at step 7")' in table.loc["raise_at_7", "traceback"]
    # the engine stopped the step at the limit: robot, step and the line it looped on
    assert re.fullmatch(r"wall-clock timeout: robot 0: step\(\) did not return within the wall "
                        r"limit of 2 s; stopped at step 0 \(t=0 s\), .*loop_forever\.py:[56]\n"
                        r"    (while True:|pass)", error["loop_forever"])
    assert re.search(r"loop_forever.py\", line [56], in step",
                     table.loc["loop_forever", "traceback"])
    assert error["exit_3"] == "the worker process died during the run (exit code 3)"
    assert error["segfault"] == ("the worker process died during the run (killed by signal "
                                 "SIGSEGV)")
    assert "Segmentation fault" in table.loc["segfault", "traceback"]
    assert "segfault.py\", line 9 in step" in table.loc["segfault", "traceback"]
    assert "non-finite reference (speed_ref=nan" in error["nan"]
    for name in ("go_to_goal", "slow_go"):
        assert table.loc[name, "status"] == "time_limit"
        assert table.loc[name, "robots"] == 2
    # every run has its folder; finished ones have their summary, failed ones their outcome
    for folder, state in zip(table["folder"], table["state"], strict=True):
        outcome = json.loads((Path(folder) / "battery.json").read_text())
        assert outcome["state"] == state
        stopped = state == "timeout" and "loop_forever" in folder  # by the engine: recorded
        assert (Path(folder) / "summary.json").exists() == (state in ("done", "error") or stopped)
    assert not any((tmp_path / "b" / "tmp").iterdir())
    assert elapsed < 60
    status = battery_status(tmp_path / "b")
    assert (status.pid, status.left, status.eta) == (None, 0, 0.0)
    assert [e[0] for e in status.errors] == [2, 3, 4, 5, 6]

    # re-running only the crashed runs: same seeds, one more attempt, the rest untouched
    again = rerun_failed(tmp_path / "b", states=("crashed",), workers=2, progress=False)
    assert again.finished == 2 and again.counts == result.counts
    after = runs_table(tmp_path / "b").set_index("algorithm")
    assert after["attempts"].to_dict() == {name: 2 if name in ("exit_3", "segfault") else 1
                                           for name in after.index}


def test_killed_and_crashed_workers_leave_no_leaked_semaphores(tmp_path: Path) -> None:
    """Python's resource tracker warned of "leaked semaphore objects" after a battery whose
    workers were killed or crashed (Numba's start-up lock, a named semaphore under the fork
    server): the battery runs in its own process, whose stderr must not have it."""
    path = write_battery(tmp_path / "killed.toml",
                         ["go_to_goal", *(fault(f) for f in ("sleep_forever", "exit_3",
                                                              "loop_forever"))],
                         seeds=1, time=1.0, timeout=1.0)
    env, marker = marked_environment()
    done = subprocess.run([sys.executable, "-m", "mimics", "battery", "run", str(path), "--out",
                           str(tmp_path / "b"), "--workers", "2"], capture_output=True,
                          text=True, timeout=600, check=False, env=env)
    assert done.returncode == 1, done.stderr
    states = runs_table(tmp_path / "b").set_index("algorithm")["state"].to_dict()
    assert states == {"go_to_goal": "done", "sleep_forever": "timeout", "exit_3": "crashed",
                      "loop_forever": "timeout"}
    assert "killed" in runs_table(tmp_path / "b").set_index("algorithm").loc[
        "sleep_forever", "error"]  # the worker's hard deadline: it never got back to Python
    assert "leaked" not in done.stderr and "resource_tracker" not in done.stderr, done.stderr
    assert left_running(marker) == []  # no worker, fork server or resource tracker left
