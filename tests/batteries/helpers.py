"""Battery files and fault algorithms for the battery tests."""

from __future__ import annotations

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
