"""Peak memory of a recorded 2000-robot, 60 s run: the recorder must stream, not hoard.

    python benchmarks/memory_2000.py [--robots 2000] [--time 60] [--scenario hospital|line]
                                     [--form team|per-robot] [--out DIR]

Each configuration runs in a fresh process (peak RSS is per process): the
run recorded into a run folder (``run_to_folder``, per-robot logs "auto", so
none above 200 robots), and the same run unrecorded for comparison. The
``line`` scenario is used with goals far enough that every robot is still
driving at the end (``distance = 2 * time``) and random initial headings (so
that the robots' rows differ and compress like real data), unless ``--scenario hospital``
names a built-in scenario that exists. Prints peak RSS, the size of
trajectory.parquet, s_sim/s, robot-steps/s and the wall time spent in the
recorder (its own clock, so a busy machine does not blur it); writes
benchmarks/results/memory_2000.json.
"""

from __future__ import annotations

import argparse
import json
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from common import add_run_options, folder_bytes, peak_rss_mb, speeds_text, write_json

RESULTS = Path(__file__).parent / "results" / "memory_2000.json"


def child(args: argparse.Namespace) -> dict[str, Any]:
    """One run in this process; returns its figures."""
    from mimics.catalog import load_scenario
    from mimics.engine.simulation import Simulation
    from mimics.records.runner import run_to_folder

    params: dict[str, Any] = {"robots": args.robots}
    if args.scenario == "line":  # still driving at the end, each robot on its own course
        params.update(distance=2.0 * args.time, random_yaw=True)
    scenario = load_scenario(args.scenario, **params)
    algorithm = "deployment" if args.scenario == "hospital" else "go_to_goal"
    algorithm += "_team" if args.form == "team" else ""
    module = __import__(f"mimics.algorithms.{algorithm}", fromlist=["step"])
    sim = Simulation(scenario, module, seed=1, time_limit=args.time, algorithm_name=algorithm)
    before = peak_rss_mb()
    start = time.perf_counter()
    figures: dict[str, Any] = {}
    if args.record:
        result = run_to_folder(sim, args.out)
        summary = json.loads((Path(args.out) / "summary.json").read_text())
        trajectory = Path(args.out) / "trajectory.parquet"
        figures = {"trajectory_bytes": trajectory.stat().st_size,
                   "trajectory_rows": summary["records"]["trajectory_rows"],
                   "write_time": summary["records"]["write_time"],
                   "recorder_time": summary["records"]["step_time"]
                   + summary["records"]["write_time"],
                   "folder_bytes": folder_bytes(Path(args.out))}
    else:
        result = sim.run()
    wall = time.perf_counter() - start
    return {"recorded": args.record, "scenario": args.scenario, "algorithm": algorithm,
            "robots": sim.state.n, "sim_time": result.sim_time, "steps": result.steps,
            "status": result.status, "wall_time": wall, "sim_speed": result.sim_time / wall,
            "robot_steps_per_s": sim.timing.count / wall, "rss_before_run_mb": before,
            "peak_rss_mb": peak_rss_mb(), **figures}


def hospital_available() -> bool:
    """True when the Hospital scenario can be built here (its Stage data is installed)."""
    from mimics.catalog import load_scenario
    from mimics.world.errors import MimicsError

    try:
        load_scenario("hospital", robots=1)
    except MimicsError:
        return False
    return True


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    add_run_options(parser, robots=2000, time=60.0)
    parser.add_argument("--scenario", choices=("hospital", "line"), default=None,
                        help="Default: hospital if its Stage data is installed, else line.")
    parser.add_argument("--form", choices=("team", "per-robot"), default="team")
    parser.add_argument("--out", type=Path, default=None, help="Keep the run folder here.")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--record", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        print(json.dumps(child(args)))
        return
    if args.scenario is None:
        args.scenario = "hospital" if hospital_available() else "line"
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = args.out or Path(tmp) / "run"
        for record in (True, False):
            command = [sys.executable, __file__, "--child", "--robots", str(args.robots),
                       "--time", str(args.time), "--scenario", args.scenario, "--form",
                       args.form, "--out", str(out)] + (["--record"] if record else [])
            done = subprocess.run(command, check=True, capture_output=True, text=True)
            rows.append(json.loads(done.stdout.strip().splitlines()[-1]))
    print(f"{args.scenario}, {args.robots} robots, {rows[0]['algorithm']}, {args.time:g} s "
          f"simulated")
    for row in rows:
        label = "recorded" if row["recorded"] else "not recorded"
        extra = (f", trajectory.parquet {row['trajectory_bytes'] / 1e6:.1f} MB "
                 f"({row['trajectory_rows']} rows), recorder {row['recorder_time']:.2f} s "
                 f"({100 * row['recorder_time'] / row['wall_time']:.1f}% of the run, "
                 f"{row['write_time']:.2f} s of it at the end)"
                 if row["recorded"] else "")
        print(f"  {label:>12}: peak RSS {row['peak_rss_mb']:.0f} MB, wall {row['wall_time']:.1f} "
              f"s, {speeds_text(row['sim_speed'], row['robot_steps_per_s'], 3)}{extra}")
    write_json(RESULTS, {"benchmark": "memory_2000", "machine": platform.platform(),
                         "python": platform.python_version(), "runs": rows})
    print(f"wrote {RESULTS}")


if __name__ == "__main__":
    main()
