"""What recording a run costs: a scenario with and without its run folder.

    python benchmarks/logging_overhead.py [--robots 60] [--repeats 5] [--warmup 1]
                                          [--scenario line] [--algorithm go_to_goal]
                                          [--time SECONDS]

Times whole runs (start to the last file written) of a scenario (by default the
paper's line with ``go_to_goal``; ``--scenario cave --algorithm deployment
--robots 100 --time 60`` is issue 39's per-robot logs bar): plain
``Simulation.run()``, and ``run_to_folder`` with the per-robot logs (60
robots: "auto" writes them) and without them.
Runs alternate between the ways so that drift hits all alike; the figures are
medians of ``--repeats`` runs after ``--warmup`` runs. Prints s_sim/s and
robot-steps/s and writes benchmarks/results/logging_overhead.json
(``logging_overhead_SCENARIO.json`` for another scenario).

Two figures of the cost: ``overhead``, the median wall time against the
unrecorded runs (end to end, but blurred by whatever else the machine does),
and ``recorder``, the time the recorder spent by its own clock (in the step
loop and at the end) over the rest of the run's time. The last line gives
what the per-robot logs alone cost: the median of each round's run with logs
over its run without them, less one.
"""

from __future__ import annotations

import argparse
import json
import platform
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

from common import add_run_options, folder_bytes, write_json

from mimics.catalog import find_algorithm, load_scenario
from mimics.engine.simulation import Simulation
from mimics.records.runner import run_to_folder

RESULTS = Path(__file__).parent / "results"


def timed_run(args: argparse.Namespace, way: str, folder: Path
              ) -> tuple[float, float, Simulation]:
    """One run of ``args``' scenario recorded ``way`` ("none", "logs" or "no_logs").

    Returns the wall time of the whole run, the part of it the recorder spent
    (by its own clock, from summary.json) and the simulation.
    """
    sim = Simulation(load_scenario(args.scenario, robots=args.robots),
                     find_algorithm(args.algorithm)[1], seed=1, time_limit=args.time)
    start = time.perf_counter()
    recorder = 0.0
    if way == "none":
        sim.run()
    else:
        run_to_folder(sim, folder, robot_logs="on" if way == "logs" else "off")
        records = json.loads((folder / "summary.json").read_text())["records"]
        recorder = records["step_time"] + records["write_time"]
    return time.perf_counter() - start, recorder, sim


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    add_run_options(parser, robots=60, repeats=5)
    parser.add_argument("--warmup", type=int, default=1)
    add_run_options(parser, scenario="line", algorithm="go_to_goal", time=None)
    args = parser.parse_args()
    ways = ("none", "logs", "no_logs")
    walls: dict[str, list[float]] = {w: [] for w in ways}
    spent: dict[str, list[float]] = {w: [] for w in ways}
    sample: dict[str, Simulation] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for attempt in range(args.warmup + args.repeats):
            for way in ways:
                wall, recorder, sim = timed_run(args, way, Path(tmp) / way)
                if attempt >= args.warmup:
                    walls[way].append(wall)
                    spent[way].append(recorder / (wall - recorder))
                    sample[way] = sim
        sizes = {w: folder_bytes(Path(tmp) / w) for w in ways if w != "none"}
    rows: dict[str, Any] = {}
    base = statistics.median(walls["none"])
    for way in ways:
        sim = sample[way]
        wall = statistics.median(walls[way])
        rows[way] = {"wall_time": wall, "wall_times": walls[way],
                     "sim_speed": sim.state.time / wall,
                     "robot_steps_per_s": sim.timing.count / wall,
                     "overhead": wall / base - 1.0,
                     "recorder_share": statistics.median(spent[way]),
                     "folder_bytes": sizes.get(way, 0)}
    print(f"{args.scenario} / {args.algorithm}, {args.robots} robots, "
          f"{sample['none'].state.step} steps, median of {args.repeats} runs after "
          f"{args.warmup} warm-up")
    print(f"{'recording':>24} {'wall s':>8} {'s_sim/s':>9} {'robot-steps/s':>14} "
          f"{'overhead':>9} {'recorder':>9} {'folder':>9}")
    labels = {"none": "none (Simulation.run)", "logs": "run folder + robot logs",
              "no_logs": "run folder, no logs"}
    for way in ways:
        r = rows[way]
        print(f"{labels[way]:>24} {r['wall_time']:8.3f} {r['sim_speed']:9.2f} "
              f"{r['robot_steps_per_s']:14.0f} {100 * r['overhead']:8.1f}% "
              f"{100 * r['recorder_share']:8.1f}% "
              f"{r['folder_bytes'] / 1e3:7.0f} kB")
    logs_cost = statistics.median(a / b - 1.0 for a, b in zip(walls["logs"], walls["no_logs"],
                                                                strict=True))
    print(f"the per-robot logs cost {100 * logs_cost:.1f}% of the run without them "
          "(median of the rounds' ratios)")
    results = RESULTS / ("logging_overhead.json" if args.scenario == "line"
                         else f"logging_overhead_{args.scenario}.json")
    write_json(results, {
        "benchmark": "logging_overhead", "scenario": args.scenario,
        "algorithm": args.algorithm, "time": args.time, "logs_cost": logs_cost,
        "robots": args.robots, "steps": sample["none"].state.step, "repeats": args.repeats,
        "warmup": args.warmup, "machine": platform.platform(), "python": platform.python_version(),
        "ways": rows})
    print(f"wrote {results}")


if __name__ == "__main__":
    main()
