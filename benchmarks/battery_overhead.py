"""The per-run cost of the battery machinery, on runs that do almost nothing.

    python benchmarks/battery_overhead.py [--runs 200] [--workers N]

A battery of ``--runs`` one-step runs (the line scenario, one robot, 0.1
simulated seconds) goes through everything a real battery does: the SQLite
state (two commits per run), the pipe to an isolated worker, the run folder
written under a temporary name and renamed, the outcome file. The same runs
are also made in this process, recorded with ``run_to_folder`` and nothing
else: the difference is the battery's overhead. Prints runs/s and ms per run.
"""

from __future__ import annotations

import argparse
import os
import sqlite3
import statistics
import tempfile
import time
from pathlib import Path

from mimics.batteries import run_battery, spec_from_dict
from mimics.records.runner import prepare, run_to_folder


def direct_ms(runs: int, root: Path) -> float:
    """Median ms per run of prepare + run_to_folder in this process."""
    times = []
    for seed in range(1, runs + 1):
        start = time.perf_counter()
        sim = prepare("line", "go_to_goal", robots=1, time=0.1, seed=seed)
        run_to_folder(sim, root / f"direct-{seed}", robot_logs="off")
        times.append(time.perf_counter() - start)
    return 1e3 * statistics.median(times[5:] or times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--runs", type=int, default=200)
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args()
    root = Path(tempfile.mkdtemp(prefix="mimics-battery-overhead-"))
    baseline = direct_ms(min(args.runs, 50), root)
    spec = spec_from_dict({"battery": {"algorithms": ["go_to_goal"], "seeds": args.runs,
                                       "time": 0.1, "timeout": 60},
                           "scenarios": [{"name": "line", "robots": 1}]})
    start = time.perf_counter()
    result = run_battery(spec, root / "battery", workers=args.workers, progress=False)
    total = time.perf_counter() - start
    assert result.counts == {"done": args.runs}, result.counts
    with sqlite3.connect(root / "battery" / "battery.db") as db:
        first, last, busy = db.execute(
            "SELECT min(started), max(ended), sum(ended - started) FROM runs").fetchone()
        in_worker = db.execute("SELECT sum(wall_time) FROM runs").fetchone()[0]
    steady = last - first
    rate = args.runs / steady
    print(f"{args.runs} one-step runs on {args.workers} worker(s), results in {root}")
    print(f"  whole battery (with worker start-up): {total:7.2f} s  "
          f"{args.runs / total:7.1f} runs/s  {1e3 * total / args.runs:7.2f} ms/run")
    print(f"  from first run to last:               {steady:7.2f} s  {rate:7.1f} runs/s  "
          f"{1e3 / rate:7.2f} ms/run")
    print(f"  per run and worker (wall x workers / runs):       "
          f"{1e3 * steady * args.workers / args.runs:7.2f} ms/run")
    print(f"  of which in the worker, start to end of the run:   "
          f"{1e3 * busy / args.runs:7.2f} ms/run (simulation: "
          f"{1e3 * in_worker / args.runs:.2f} ms)")
    print(f"  the same run made directly in-process:             {baseline:7.2f} ms/run")
    print(f"  battery overhead per run and worker:               "
          f"{1e3 * steady * args.workers / args.runs - baseline:7.2f} ms/run")


if __name__ == "__main__":
    main()
