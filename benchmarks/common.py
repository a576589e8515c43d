"""Shared helpers for the benchmark scripts: timing medians, RSS, the results file.

Benchmarks are run by hand (never by the test suite); each prints a table and
merges its figures into ``benchmarks/results.json``.
"""

from __future__ import annotations

import json
import resource
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from mimics.engine.simulation import Simulation

RESULTS = Path(__file__).with_name("results.json")


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far (MB)."""
    usage = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return usage / 1024 if sys.platform != "darwin" else usage / 1024 / 1024


def time_runs(make: Callable[[], Simulation], repeats: int = 3, warmup: int = 1
              ) -> dict[str, Any]:
    """Run fresh simulations ``warmup + repeats`` times; medians of the timed ones.

    Returns sim seconds per wall second, robot-steps per second and rays per
    second (beams cast by active robots), with the raw wall times.
    """
    walls: list[float] = []
    sample: dict[str, Any] = {}
    for attempt in range(warmup + repeats):
        sim = make()
        robot_steps = 0
        rays = 0
        sim.start()
        start = time.perf_counter()
        while True:
            active = sim.state.active
            robot_steps += int(active.sum())
            rays += int(sim.types.beam_count[active].sum())
            if not sim.step():
                break
        wall = time.perf_counter() - start
        if attempt >= warmup:
            walls.append(wall)
            sample = {"sim_time": sim.state.time, "robot_steps": robot_steps, "rays": rays,
                      "status": sim.status, "robots": sim.state.n}
    wall = statistics.median(walls)
    return {**sample, "wall_time": wall, "wall_times": walls,
            "sim_speed": sample["sim_time"] / wall,
            "robot_steps_per_s": sample["robot_steps"] / wall,
            "rays_per_s": sample["rays"] / wall, "peak_rss_mb": peak_rss_mb()}


def save(section: str, rows: list[dict[str, Any]] | dict[str, Any]) -> None:
    """Merge ``rows`` under ``section`` into benchmarks/results.json."""
    data = json.loads(RESULTS.read_text()) if RESULTS.exists() else {}
    data[section] = rows
    RESULTS.write_text(json.dumps(data, indent=2) + "\n")


def print_table(title: str, rows: list[dict[str, Any]], columns: list[str]) -> None:
    """A plain fixed-width table on stdout."""
    print(title)
    print("  ".join(f"{c:>14}" for c in columns))
    for row in rows:
        cells = []
        for c in columns:
            value = row.get(c, "")
            cells.append(f"{value:>14.4g}" if isinstance(value, float) else f"{value!s:>14}")
        print("  ".join(cells))
