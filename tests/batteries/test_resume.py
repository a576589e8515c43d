"""A battery killed with SIGKILL midway, then resumed: nothing lost, nothing repeated."""

from __future__ import annotations

import re
import sqlite3
import sys
from collections import Counter
from pathlib import Path

import pandas as pd
import pytest

from mimics.batteries import resume_battery, run_battery, runs_table
from mimics.batteries.status import battery_status
from mimics.world.errors import MimicsError
from tests.batteries.helpers import OUTCOME_COLUMNS, all_gone, fault, kill_midway, write_battery

pytestmark = pytest.mark.skipif(sys.platform == "win32", reason="SIGKILL is POSIX")


def done_rows(db_path: Path) -> dict[int, int]:
    with sqlite3.connect(db_path) as db:
        return dict(db.execute("SELECT id, attempts FROM runs WHERE state = 'done'"))


def outcome_file(folder: Path, run_id: int) -> Path:
    """The outcome file (battery.json) in a run's folder."""
    return next((folder / "runs").glob(f"{run_id:05d}-*")) / "battery.json"


def executions(folder: Path) -> Counter[int]:
    """How many times each run started in a worker (from the workers' logs)."""
    counts: Counter[int] = Counter()
    for log in (folder / "workers").glob("*.log"):
        counts.update(int(m) for m in re.findall(r"^--- mimics battery: run (\d+) ",
                                                 log.read_text(), flags=re.M))
    return counts


def test_killed_battery_resumes_without_losing_or_repeating_runs(tmp_path: Path) -> None:
    path = write_battery(tmp_path / "b.toml", [fault("slow_go"), "go_to_goal"], seeds=8,
                         time=2.0, scenarios=[{"name": "line", "robots": [1, 2]}])
    killed = tmp_path / "killed"
    workers = kill_midway(path, killed, runs=3)
    db = killed / "battery.db"
    before = done_rows(db)
    with sqlite3.connect(db) as connection:
        total = connection.execute("SELECT count(*) FROM runs").fetchone()[0]
    assert 3 <= len(before) < total == 32
    outcome_before = {i: outcome_file(killed, i).read_text() for i in before}
    assert all_gone(workers)  # the workers die with the battery, even after a SIGKILL
    status = battery_status(killed)
    assert status.pid is None and status.left == total - len(before)

    result = resume_battery(killed, workers=2, progress=False)
    assert result.counts == {"done": total}
    after = runs_table(killed)
    for run_id, attempts in before.items():  # finished runs kept as they were
        row = after[after["id"] == run_id].iloc[0]
        assert row["attempts"] == attempts == 1
        assert Path(row["folder"], "battery.json").read_text() == outcome_before[run_id]
    started = executions(killed)
    assert all(started[i] == 1 for i in before)  # none ran twice
    assert set(started) == set(range(1, total + 1))
    assert max(started.values()) <= 2  # only runs cut by the kill ran again
    with pytest.raises(MimicsError, match="already holds a battery"):
        run_battery(path, killed, workers=1, progress=False)

    # the report equals that of a battery never interrupted
    reference = run_battery(path, tmp_path / "reference", workers=2, progress=False)
    assert reference.counts == {"done": total}
    expected = runs_table(tmp_path / "reference")[OUTCOME_COLUMNS]
    pd.testing.assert_frame_equal(after[OUTCOME_COLUMNS], expected)
    assert (after["reached_goal"] >= 0).all()
