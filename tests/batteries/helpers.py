"""Battery files, fault algorithms, and killing a battery midway, for the battery tests."""

from __future__ import annotations

import contextlib
import os
import re
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import tomli_w

FAULTS = Path(__file__).parent / "faults"
#: Columns that a battery must reproduce exactly (not times, workers or attempts).
OUTCOME_COLUMNS = ["algorithm", "scenario", "parameters", "seed", "state", "status", "robots",
                   "reached_goal", "collisions", "escaped", "deadlocks", "livelocks",
                   "exceptions", "sim_time"]


def fault(name: str) -> str:
    """The absolute path of a fault algorithm (``raise_at_7``, ``segfault``...)."""
    return str(FAULTS / f"{name}.py")


def write_battery(path: Path, algorithms: list[str], *, scenarios: list[dict[str, Any]] | None
                  = None, **battery: Any) -> Path:
    """Write a battery file (short runs by default) and return its path."""
    table = {"algorithms": algorithms, "seeds": 1, "time": 1.0, "timeout": 5.0, **battery}
    data = {"battery": table, "scenarios": scenarios or [{"name": "line", "robots": 2}]}
    path.write_text(tomli_w.dumps(data))
    return path


def start_battery_process(battery: Path, out: Path) -> subprocess.Popen[bytes]:
    """``mimics battery run BATTERY --out OUT --workers 2`` in a process of its own (to be
    killed by the test), its output discarded."""
    code = ("import sys; from mimics.interfaces.cli.battery import app; "
            "app(sys.argv[1:], prog_name='mimics battery')")
    return subprocess.Popen(
        [sys.executable, "-c", code, "run", str(battery), "--out", str(out), "--workers", "2",
         "--no-progress"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)


def alive(pid: int) -> bool:
    """Whether a process runs (a zombie does not count)."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False
    except OSError:  # no /proc: ask the kernel
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        return True



def done_count(db: Path, where: str = "1") -> int:
    """How many runs of a battery database have finished (of those ``where`` selects)."""
    with sqlite3.connect(db) as connection:
        return int(connection.execute(f"SELECT count(*) FROM runs WHERE state = 'done' "
                                      f"AND ({where})").fetchone()[0])


def kill_midway(battery: Path, out: Path, runs: int, where: str = "1",
                seconds: float = 60.0) -> list[int]:
    """Run ``battery`` into ``out`` in a process of its own, SIGKILL it once ``runs`` runs
    (of those the SQL condition ``where`` selects) have finished (``seconds`` at most;
    failing if it ends first), and return the process ids of the workers its database
    names."""
    process = start_battery_process(battery, out)
    db = out / "battery.db"
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        with contextlib.suppress(sqlite3.Error):  # the database may be half made yet
            if db.exists() and done_count(db, where) >= runs:
                break
        assert process.poll() is None, "the battery ended before it could be killed"
        time.sleep(0.02)
    os.kill(process.pid, signal.SIGKILL)
    process.wait()
    return worker_pids(db)


def worker_pids(db: Path) -> list[int]:
    """The process ids of the workers a battery database names."""
    with sqlite3.connect(db) as connection:
        return [int(pid) for (label,) in connection.execute(
            "SELECT worker FROM runs WHERE worker IS NOT NULL")
            for pid in re.findall(r"pid (\d+)", label)]


def all_gone(pids: list[int], seconds: float = 5.0) -> bool:
    """Whether every process of ``pids`` has ended within ``seconds``."""
    stop = time.monotonic() + seconds
    while any(alive(pid) for pid in pids) and time.monotonic() < stop:
        time.sleep(0.05)
    return not any(alive(pid) for pid in pids)
