"""Battery files and fault algorithms for the battery tests."""

from __future__ import annotations

import os
import subprocess
import sys
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

