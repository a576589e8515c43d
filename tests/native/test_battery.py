"""A C algorithm that crashes ends its run as crashed, with the signal; the battery goes on."""

from __future__ import annotations

from pathlib import Path

import pytest

from mimics.batteries import run_battery, runs_table
from tests.batteries.helpers import write_battery
from tests.native.conftest import ALGORITHMS, EXAMPLES


def test_crashes_are_recorded_with_their_signal_and_the_other_runs_finish(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MIMICS_CONFIG_DIR", str(tmp_path / "config"))  # not the user's
    algorithms = [str(EXAMPLES / "c" / "go_to_goal.c"), str(ALGORITHMS / "crash.c"),
                  str(ALGORITHMS / "abort.c")]
    path = write_battery(tmp_path / "native.toml", algorithms, seeds=2, time=1.0, timeout=20.0,
                         scenarios=[{"name": "line", "robots": 3}])
    result = run_battery(path, tmp_path / "b", workers=2, progress=False)
    assert result.counts == {"done": 2, "crashed": 4}
    table = runs_table(tmp_path / "b")
    for _, row in table.iterrows():
        if row["algorithm"] == "go_to_goal":
            assert (row["state"], row["status"], row["robots"]) == ("done", "time_limit", 3)
            continue
        signal = {"crash": "SIGSEGV", "abort": "SIGABRT"}[row["algorithm"]]
        assert row["state"] == "crashed"
        assert row["error"] == ("the worker process died during the run (killed by signal "
                                f"{signal})")
        assert "Fatal Python error" in row["traceback"]  # the worker's fault handler


def test_a_c_step_that_never_returns_is_cut_at_the_timeout(tmp_path: Path) -> None:
    path = write_battery(tmp_path / "spin.toml", [str(ALGORITHMS / "spin.c")], seeds=2,
                         time=1.0, timeout=1.0, scenarios=[{"name": "line", "robots": 3}])
    result = run_battery(path, tmp_path / "b", workers=1, progress=False)
    assert result.counts == {"timeout": 2}
    table = runs_table(tmp_path / "b")
    assert set(table["error"]) == {"wall-clock timeout: robot 1: mimics_step in spin.c did not "
                                   "return within the wall limit of 1 s; stopped at step 3 "
                                   "(t=0.3 s)"}
    assert set(table["worker"]) == {table["worker"][0]}  # cut, not killed: the worker goes on
    assert set(table["sim_time"]) == {0.3}
