"""Where a battery run's time goes, and the runs/s of a Figure 2 subset.

    python benchmarks/battery_overhead.py [--robots 1 30 60] [--runs 20] [--seeds 4]
                                          [--workers 2] [--repeats 3] [--quick]

Two parts (issue 21, part 5: the Figure 2 battery, 1,800 short runs, in <= 30 s
on 2 workers):

* per run, in this process, for each ``--robots``: ``--runs`` runs of the line
  scenario (21.8 simulated s, go_to_goal, robot logs off) go through the
  worker's :func:`mimics.batteries.tasks.execute` and the parent's side of a
  real battery folder (SQLite ``start``/``task``/``set_worker``, then
  :func:`mimics.batteries.driver.finish`: outcome file, rename, commit). Each is
  split into ms per run: the build (``prepare``: scenario, checks,
  ``Simulation``), the simulation steps (the engine's wall time less the
  recorder's share), recording (``on_start``/``on_step`` plus writing at the
  end, as the recorder counts them), the rest of ``execute``, and the parent's
  store and rename. Medians over the runs, after one warm-up run.
* the battery: ``benchmarks/paper_figure2.toml`` with ``--seeds`` seeds (4:
  240 runs) run by ``run_battery`` on ``--workers`` workers, ``--repeats``
  times: the median of its wall time and runs/s, and the 1,800 runs of the
  full battery at that rate.

Numba runs on one thread in this process (as in each of 2 workers on 2 cores)
unless ``--threads``. ``--no-logging`` is accepted for run_all.py and ignored
(a battery always records). Figures merge into benchmarks/results.json under
``battery_overhead``.
"""

from __future__ import annotations

import argparse
import json
import statistics
import tempfile
import time
import tomllib
from pathlib import Path
from typing import Any

from common import RESULTS, add_run_options, save

import mimics.records.runner as runner
from mimics.batteries import run_battery, spec_from_dict
from mimics.batteries.driver import finish
from mimics.batteries.store import BatteryStore
from mimics.batteries.tasks import execute
from mimics.batteries.workers import warm_up_engine

FIGURE2 = Path(__file__).with_name("paper_figure2.toml")
FULL_RUNS = 1800
PARTS = ["build", "steps", "recording", "worker_other", "parent", "total"]


def figure2_spec(seeds: int, robots: list[int] | None = None) -> Any:
    """The Figure 2 battery with ``seeds`` seeds (and only ``robots`` if given)."""
    data = tomllib.loads(FIGURE2.read_text())
    data["battery"]["seeds"] = seeds
    if robots is not None:
        data["scenarios"][0]["robots"] = robots
    return spec_from_dict(data)


def per_run_parts(robots: int, runs: int, root: Path) -> dict[str, float]:
    """Median ms per run of each part, over ``runs`` runs of ``robots`` robots."""
    store = BatteryStore.create(root / f"robots-{robots}", figure2_spec(runs + 1, [robots]))
    spec = store.spec()
    built: list[float] = []
    real_prepare = runner.prepare

    def timed_prepare(*args: Any, **kwargs: Any) -> Any:
        began = time.perf_counter()
        try:
            return real_prepare(*args, **kwargs)
        finally:
            built.append(time.perf_counter() - began)

    runner.prepare = timed_prepare  # execute imports it from the module at each call
    rows: list[dict[str, float]] = []
    try:
        for run_id in store.ids("pending"):
            began = time.perf_counter()
            attempt = store.start(run_id)
            task = store.task(run_id, attempt, spec, store.folder / "tmp" / f"{run_id}")
            store.set_worker(run_id, "in-process")
            parent = time.perf_counter() - began
            began = time.perf_counter()
            outcome = execute(task, "in-process")
            worker = time.perf_counter() - began
            began = time.perf_counter()
            finish(store, task, outcome)
            parent += time.perf_counter() - began
            assert outcome.state == "done", outcome.error
            summary = json.loads((store.run_folder(run_id) / "summary.json").read_text())
            records = summary["records"]
            recording = records["step_time"] + records["write_time"]
            steps = summary["wall_time"] - records["step_time"]
            rows.append({"build": built[-1], "steps": steps, "recording": recording,
                         "worker_other": worker - built[-1] - steps - recording,
                         "parent": parent, "total": worker + parent})
    finally:
        runner.prepare = real_prepare
        store.close()
    rows = rows[1:]  # the first run of a size warms its caches up
    return {part: 1e3 * statistics.median(r[part] for r in rows) for part in PARTS}


def battery_rate(seeds: int, workers: int, root: Path, repeat: int) -> dict[str, float]:
    """One run of the Figure 2 subset: wall seconds and runs/s."""
    spec = figure2_spec(seeds)
    began = time.perf_counter()
    result = run_battery(spec, root / f"battery-{repeat}", workers=workers, progress=False)
    elapsed = time.perf_counter() - began
    runs = sum(result.counts.values())
    assert result.counts == {"done": runs}, result.counts
    return {"runs": runs, "seconds": elapsed, "runs_per_s": runs / elapsed}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--robots", type=int, nargs="+", default=None,
                        help="robot counts of the per-run split (default 1 30 60; 1 10 quick)")
    parser.add_argument("--runs", type=int, default=None,
                        help="runs per robot count (default 20; 5 with --quick)")
    parser.add_argument("--seeds", type=int, default=None,
                        help="seeds of the battery subset (default 4: 240 runs; 1 quick)")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeats", type=int, default=None,
                        help="battery repeats, median reported (default 3; 1 with --quick)")
    parser.add_argument("--threads", type=int, default=1,
                        help="Numba threads of the in-process runs (default 1)")
    parser.add_argument("--no-logging", dest="logging", action="store_false",
                        help="ignored: a battery always records")
    parser.add_argument("--quick", action="store_true", help="a short smoke run")
    add_run_options(parser, results=RESULTS)
    args = parser.parse_args()
    robots = args.robots or ([1, 10] if args.quick else [1, 30, 60])
    runs = args.runs or (5 if args.quick else 20)
    seeds = args.seeds or (1 if args.quick else 4)
    repeats = args.repeats or (1 if args.quick else 3)
    import numba

    numba.set_num_threads(min(args.threads, numba.config.NUMBA_NUM_THREADS))
    warm_up_engine()
    root = Path(tempfile.mkdtemp(prefix="mimics-battery-overhead-"))
    print(f"per run (ms, median of {runs - 1} after one warm-up; line, go_to_goal, 21.8 s, "
          f"robot logs off; {args.threads} Numba thread(s), in this process)")
    print(f"{'robots':>6} " + " ".join(f"{p:>12}" for p in PARTS))
    rows = []
    for n in robots:
        parts = per_run_parts(n, runs, root)
        rows.append({"robots": n, **parts})
        print(f"{n:>6} " + " ".join(f"{parts[p]:>12.2f}" for p in PARTS), flush=True)
    spec_runs = len(figure2_spec(seeds).runs())
    print(f"\nbattery: {FIGURE2.name} with {seeds} seed(s) ({spec_runs} runs) on "
          f"{args.workers} workers, {repeats} repeat(s)")
    batteries = []
    for repeat in range(repeats):
        batteries.append(battery_rate(seeds, args.workers, root, repeat))
        b = batteries[-1]
        print(f"  {b['seconds']:7.1f} s  {b['runs_per_s']:6.2f} runs/s", flush=True)
    seconds = statistics.median(b["seconds"] for b in batteries)
    rate = statistics.median(b["runs_per_s"] for b in batteries)
    print(f"  median {seconds:.1f} s, {rate:.2f} runs/s: the {FULL_RUNS} runs of the full "
          f"battery in about {FULL_RUNS / rate:.0f} s (target <= 30 s on a quiet machine)")
    save("battery_overhead", {
        "meta": {"robots": robots, "runs": runs, "seeds": seeds, "workers": args.workers,
                 "repeats": repeats, "threads": args.threads, "quick": args.quick,
                 "measured": time.strftime("%Y-%m-%dT%H:%M:%S%z")},
        "rows": rows, "batteries": batteries,
        "summary": {"runs": spec_runs, "seconds": seconds, "runs_per_s": rate,
                    "full_battery_s": FULL_RUNS / rate}}, args.results)
    print(f"results in {root}; figures merged into {args.results}")


if __name__ == "__main__":
    main()
