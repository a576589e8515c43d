"""The per-robot call cost alone: what calling user code once per robot costs the engine.

    python benchmarks/call_overhead.py [--scenario cave] [--time 10] [--repeats 7]
                                       [--logging] [--threads N] [--quick]

100 robots in the Cave (``--scenario line`` for the line of 100 Pioneer3AT)
run three algorithms that leave every robot standing still, so that the
engine does the same work in all three (deadlock deactivation is turned off
so that every robot stays active):

* ``team_constant``: ``team_step(team)`` returning zeros and the headings,
  one call per step: the engine's cost with (almost) no user-call overhead;
* ``constant``: ``def step(robot): return 0.0, robot.heading``;
* ``reads_scan``: the same after reading ``robot.scan.ranges`` and ``robot.pose``.

µs per call = (wall time per step of the per-robot form - that of
``team_constant``) / robots, the median over ``--repeats`` rounds; each
round runs the three one after another in one fresh process (after a warm-up
of each), so that they see the same machine. Also printed: the time spent
inside the calls by the engine's own clock (``sim.timing``). Runs are not
recorded unless ``--logging``. The difference is small against the step, so
on a busy machine use the default 7 rounds or more, and ``--threads 1`` (the
per-robot calls run on one thread anyway). Merges the figures into
benchmarks/results.json under ``call_overhead``.
"""

from __future__ import annotations

import statistics
from typing import Any

import numpy as np
from common import benchmark_parser, parse_or_serve_child, run_child, save_measured, time_runs


def constant(robot: Any) -> tuple[float, float]:
    """Stand still: the cheapest valid per-robot step."""
    return 0.0, robot.heading


def reads_scan(robot: Any) -> tuple[float, float]:
    """Stand still after reading the scan and the pose."""
    ranges = robot.scan.ranges
    _x, _y, theta = robot.pose
    return 0.0 * float(ranges[0]), float(theta)


class TeamConstant:
    """Stand still, the whole team in one call."""

    def team_step(self, team: Any) -> tuple[np.ndarray, np.ndarray]:
        """Zero speed and the current headings for every active robot."""
        pose = team.pose
        return np.zeros(len(pose)), np.array(pose[:, 2])


ALGORITHMS: dict[str, Any] = {"team_constant": TeamConstant, "constant": constant,
                              "reads_scan": reads_scan}


def child(spec: dict[str, Any]) -> dict[str, Any]:
    """Warm up each algorithm, then ``repeats`` rounds of the three; per-round figures."""
    from mimics.catalog import load_scenario
    from mimics.engine.simulation import Simulation

    params = {"robots": spec["robots"]} if spec["scenario"] == "line" else {}
    scenario = load_scenario(spec["scenario"], **params).with_settings(
        deactivate_on_deadlock=False)
    made: list[Simulation] = []

    def make(name: str, limit: float) -> Any:
        def build() -> Simulation:
            made.append(Simulation(scenario, ALGORITHMS[name], seed=1, time_limit=limit,
                                   algorithm_name=name))
            return made[-1]
        return build

    for name in ALGORITHMS:
        time_runs(make(name, spec["warmup_time"]), repeats=1, warmup=0)
    rounds: dict[str, list[dict[str, float]]] = {name: [] for name in ALGORITHMS}
    for _ in range(spec["repeats"]):
        for name in ALGORITHMS:
            figures = time_runs(make(name, spec["time"]), repeats=1, warmup=0,
                                logging=spec["logging"])
            sim = made[-1]
            rounds[name].append({
                "us_per_step": 1e6 * figures["wall_time"] / max(figures["steps"], 1),
                "cpu_us_per_step": 1e6 * figures["cpu_time"] / max(figures["steps"], 1),
                "inside_us_per_call": 1e6 * sim.timing.total / max(sim.timing.count, 1),
                "robots": figures["robots"], "steps": figures["steps"],
                "robot_steps": figures["robot_steps"], "peak_rss_mb": figures["peak_rss_mb"],
                "threads": figures["threads"]})
    return rounds


def main() -> None:
    parser = benchmark_parser(__doc__, time=10.0, quick_time=2.0, repeats=7, quick_repeats=2)
    parser.add_argument("--logging", dest="logging", action="store_true",
                        help="record the runs like `mimics run` (default: not recorded)")
    parser.add_argument("--scenario", choices=("cave", "line"), default="cave")
    parser.add_argument("--robots", type=int, default=100, help="line only (the Cave has 100)")
    parser.set_defaults(logging=False)
    args = parse_or_serve_child(parser, child=child)
    if args is None:
        return
    spec = {"scenario": args.scenario, "robots": args.robots, "time": args.time,
            "warmup_time": args.warmup_time, "repeats": args.repeats, "logging": args.logging}
    rounds = run_child(__file__, spec, args.threads)
    base = rounds["team_constant"]
    robots = base[0]["robots"]
    print(f"{args.scenario}, {robots} robots standing still, {base[0]['steps']} steps per run, "
          f"{args.repeats} rounds, logging {'on' if args.logging else 'off'}, "
          f"{base[0]['threads']} numba thread(s)")
    print(f"  {'algorithm':>14} {'us/step':>10} {'us/call':>10} {'inside call':>12} "
          f"{'CPU us/call':>12}")
    print(f"  {'team_constant':>14} {statistics.median(r['us_per_step'] for r in base):10.1f} "
          f"{'(engine)':>10} {statistics.median(r['inside_us_per_call'] for r in base):10.2f}"
          f"  (team call, per robot)")
    rows: list[dict[str, Any]] = []
    for name in ("constant", "reads_scan"):
        mine = rounds[name]
        per_call = [(r["us_per_step"] - b["us_per_step"]) / robots for r, b in zip(mine, base,
                                                                                  strict=True)]
        row = {"benchmark": "call_overhead", "form": "per-robot", "algorithm": name,
               "scenario": args.scenario, "robots": robots,
               "us_per_step": statistics.median(r["us_per_step"] for r in mine),
               "engine_us_per_step": statistics.median(r["us_per_step"] for r in base),
               "us_per_call": statistics.median(per_call), "us_per_call_rounds": per_call,
               "cpu_us_per_call": statistics.median(
                   (r["cpu_us_per_step"] - b["cpu_us_per_step"]) / robots
                   for r, b in zip(mine, base, strict=True)),
               "inside_us_per_call": statistics.median(r["inside_us_per_call"] for r in mine),
               "sim_time": args.time, "logging": args.logging, "threads": mine[0]["threads"],
               "peak_rss_mb": max(r["peak_rss_mb"] for r in mine)}
        rows.append(row)
        print(f"  {name:>14} {row['us_per_step']:10.1f} {row['us_per_call']:10.2f} "
              f"{row['inside_us_per_call']:12.2f} {row['cpu_us_per_call']:12.2f}")
    print("  us/call: (per-step wall time - team_constant's) / robots, median of the rounds;"
          " inside call: the engine's own clock around step(robot); CPU us/call: the same"
          " difference in process CPU time (all threads)")
    save_measured(args, "call_overhead", rows, rounds=rounds)


if __name__ == "__main__":
    main()
