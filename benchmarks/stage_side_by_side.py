"""mimics beside Stage 4.3 as whole processes: the Cave's 60 s and the Hospital's 10 s.

    python benchmarks/stage_side_by_side.py [--repeats 3] [--only cave,cave_team,hospital_team]

Each row is one ``mimics run SCENARIO ALGORITHM --time T`` command, timed as a
whole process from start to exit (logging on, as a user runs it) with Numba's
cache, the map cache and Python's bytecode cache warm (an untimed 0.1 s run
first). Rows alternate within each repeat, so that all meet the same minutes
of a busy machine. Printed per row, medians and ranges of ``--repeats`` runs:

* the whole process's wall time and its speed, ``T`` / wall (s_sim/s);
* the loop's own speed (the summary's ``sim_speed``);
* the whole-process speed over Stage's, against each end of Stage's range;
* the same by CPU time, ``T`` / (user + sys seconds of the process): on a
  loaded machine the wall time is mostly waiting for a core, and as long as
  the process does not sleep, its CPU time is at least its wall time on an
  idle machine (more, when its two threads overlap), so the CPU speed is a
  floor of the idle machine's whole-process speed.

Stage's figures are those of ``../shared/peers/stage.md`` beside the repository (Stage 4.3 built
from source, headless, the same worlds, on the project's 2-core machine, as a
whole process): the Cave with 100 robots tracing their 180-beam 8 m lasers,
60 s, 2.79 to 3.64 s_sim/s; the Hospital with 2,000 robots, IR and a 2 m
laser, 10 s, 0.295 to 0.455 s_sim/s. Issue 39's bars, as whole processes:
Cave >= 20x Stage per-robot and >= 25x team, Hospital >= 15x. Merges the
figures into benchmarks/results.json under ``stage_side_by_side``.
"""

from __future__ import annotations

import argparse
import json
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import RESULTS, add_run_options, save, spread
from startup import whole_process_env

#: Stage 4.3's whole-process speeds on this machine (s_sim/s, lowest and highest measured).
STAGE = {"cave": (2.79, 3.64), "hospital": (0.295, 0.455)}
ROWS = {
    "cave": ("cave", "deployment", 60.0, 20.0),
    "cave_team": ("cave", "deployment_team", 60.0, 25.0),
    "hospital": ("hospital", "deployment", 10.0, 15.0),
    "hospital_team": ("hospital", "deployment_team", 10.0, 15.0),
}


def one_run(scenario: str, algorithm: str, sim_time: float, out: Path) -> dict[str, float]:
    """Wall and CPU seconds of one whole ``mimics run`` process, and its loop's speed."""
    shutil.rmtree(out, ignore_errors=True)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    began = time.perf_counter()
    subprocess.run([sys.executable, "-m", "mimics", "run", scenario, algorithm, "--time",
                    str(sim_time), "--out", str(out)], check=True, stdout=subprocess.DEVNULL,
                   env=whole_process_env())
    wall = time.perf_counter() - began
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    summary = json.loads((out / "summary.json").read_text())
    return {"wall": wall, "cpu": cpu, "speed": sim_time / wall, "cpu_speed": sim_time / cpu,
            "loop_speed": summary["sim_speed"]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_run_options(parser, repeats=3, results=RESULTS)
    parser.add_argument("--only", default=",".join(ROWS))
    args = parser.parse_args()
    names = args.only.split(",")
    runs: dict[str, list[dict[str, float]]] = {name: [] for name in names}
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "run"
        for name in names:  # warm the caches (Numba's, the map's, Python's bytecode)
            scenario, algorithm, _, _ = ROWS[name]
            one_run(scenario, algorithm, 0.1, out)
        for k in range(args.repeats):
            for name in (names if k % 2 == 0 else list(reversed(names))):
                scenario, algorithm, sim_time, _ = ROWS[name]
                runs[name].append(one_run(scenario, algorithm, sim_time, out))
    figures: dict[str, dict[str, object]] = {}
    print("whole processes, medians (range); Stage 4.3 from ../shared/peers/stage.md")
    for name in names:
        scenario, algorithm, sim_time, bar = ROWS[name]
        rows = runs[name]
        speed = statistics.median(row["speed"] for row in rows)
        low, high = STAGE[scenario]
        print(f"mimics run {scenario} {algorithm} --time {sim_time:g}   (bar: >= {bar:g}x Stage)")
        column = {key: [row[key] for row in rows] for key in rows[0]}
        print(f"  whole {spread(column['wall'])} s, cpu {spread(column['cpu'])} s -> "
              f"{spread(column['speed'])} s_sim/s; loop alone {spread(column['loop_speed'], 1)}"
              " s_sim/s")
        cpu_speed = statistics.median(column["cpu_speed"])
        print(f"  Stage {low:g}-{high:g} s_sim/s: {speed / high:.1f}x to {speed / low:.1f}x; by "
              f"CPU time ({cpu_speed:.2f} s_sim/s) {cpu_speed / high:.1f}x to "
              f"{cpu_speed / low:.1f}x")
        figures[name] = {
            "command": f"mimics run {scenario} {algorithm} --time {sim_time:g}",
            "whole_wall_median_s": statistics.median(row["wall"] for row in rows),
            "cpu_median_s": statistics.median(row["cpu"] for row in rows),
            "whole_speed_median": speed,
            "loop_speed_median": statistics.median(row["loop_speed"] for row in rows),
            "stage_speed_range": [low, high],
            "ratio_to_stage": [speed / high, speed / low],
            "cpu_speed_median": cpu_speed,
            "cpu_ratio_to_stage": [cpu_speed / high, cpu_speed / low],
            "bar_ratio": bar}
    save("stage_side_by_side", figures, args.results)


if __name__ == "__main__":
    main()
