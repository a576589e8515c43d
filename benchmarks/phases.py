"""Where a step goes: wall time of each phase of the step, per step, over one run.

    python benchmarks/phases.py [--scenario cave] [--algorithm deployment_team]
                                [--time 60] [--robots N [N ...]] [--runs 1]
                                [--robot-logs auto|on|off] [--no-logging]
                                [--first-steps K]

Wraps the step's phases (the ``Simulation`` methods a step calls, the kernels
it calls and the recorder's hooks) in wall-clock timers, runs the scenario
once to warm up and ``--runs`` times timed, and prints milliseconds per step
for each, largest first (the median of the runs). Phases nest (``_sense`` holds
``trace_beams``), so the column does not add up to the total. Unlike the
other benchmarks this one reaches into the engine's private methods: it is a
profiler, its names may change with the engine.

With several ``--robots`` (a scenario with that parameter, e.g. ``--scenario
swarm --algorithm dispersion_team --robots 100 10000``) it prints nanoseconds
per robot-step of each phase at each size instead, and what each phase costs
per step at the smallest size beyond the largest size's rate: where the cost
per robot-step is not flat in the team size (issue 21's swarm bar).

With ``--first-steps K`` it times one fresh run's set-up instead (the
scenario's load, ``Simulation()``, ``start()``) and its first ``K`` steps one
by one, each phase of the first step beside its median over steps 2..K (issue
39: the first step no slower than the next ones), e.g. ``--scenario swarm
--algorithm dispersion_team --robots 100000 --first-steps 5 --robot-logs off``.
"""

from __future__ import annotations

import argparse
import collections
import statistics
import tempfile
import time
from collections.abc import Callable
from typing import Any

from common import add_run_options

import mimics.engine.motion_checks as motion_checks_module
import mimics.engine.ranging.scanner as scanner_module
import mimics.engine.simulation as simulation_module
from mimics.catalog import find_algorithm, load_scenario
from mimics.engine.simulation import Simulation
from mimics.records.recorder import RunRecorder

STEP_PHASES = ["_move", "_check_moved", "_mark_departures_and_arrivals", "_check_stalls",
               "_finish_deactivations", "_sense", "_robot_index", "_check_end",
               "_handle_failures"]
# each kernel in the module that calls it (where the wrapper must replace it)
KERNELS = {"trace_beams": scanner_module, "measure_positioning": simulation_module,
           "_check_kernel": motion_checks_module, "index_robots": simulation_module,
           "update_odometry": simulation_module}
RECORDER_HOOKS = ["on_step", "on_end"]

totals: collections.defaultdict[str, float] = collections.defaultdict(float)


def timed(owner: Any, name: str, label: str) -> None:
    """Replace ``owner.name`` by a wrapper adding its wall time to ``totals[label]``."""
    inner: Callable[..., Any] = getattr(owner, name)

    def wrapper(*args: Any, **kwargs: Any) -> Any:
        start = time.perf_counter()
        try:
            return inner(*args, **kwargs)
        finally:
            totals[label] += time.perf_counter() - start

    setattr(owner, name, wrapper)


def measure(args: argparse.Namespace, robots: int | None) -> tuple[Simulation, float,
                                                                  dict[str, float]]:
    """One warm-up run and ``args.runs`` timed runs of ``robots`` robots (None: the
    scenario's own); the last run, the median wall time and each phase's median."""
    algorithm = find_algorithm(args.algorithm)[1]
    params = {} if robots is None else {"robots": robots}
    scenario = load_scenario(args.scenario, **params)
    walls: list[float] = []
    phases: collections.defaultdict[str, list[float]] = collections.defaultdict(list)
    for run in range(1 + args.runs):  # the first one warms up
        sim = Simulation(scenario, algorithm, seed=1, time_limit=args.time)
        with tempfile.TemporaryDirectory(prefix="mimics-phases-") as folder:
            if not args.no_logging:
                sim.observers.append(RunRecorder(folder, robot_logs=args.robot_logs))
            timed(sim.controller, "compute", "algorithm (controller.compute)")
            sim.start()
            totals.clear()
            start = time.perf_counter()
            while sim.step():
                pass
            wall = time.perf_counter() - start
        if run:
            walls.append(wall)
            for label, seconds in totals.items():
                phases[label].append(seconds)
    return sim, statistics.median(walls), {label: statistics.median(values)
                                           for label, values in phases.items()}


def first_steps(args: argparse.Namespace) -> None:
    """Time the set-up and the first ``args.first_steps`` steps of one run, phase by phase."""
    algorithm = find_algorithm(args.algorithm)[1]
    params = {} if args.robots is None else {"robots": args.robots[0]}
    began = time.perf_counter()
    scenario = load_scenario(args.scenario, **params)
    loaded = time.perf_counter()
    sim = Simulation(scenario, algorithm, seed=1, time_limit=args.time)
    built = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="mimics-phases-") as folder:
        if not args.no_logging:
            sim.observers.append(RunRecorder(folder, robot_logs=args.robot_logs))
        timed(sim.controller, "compute", "algorithm (controller.compute)")
        sim.start()
        started = time.perf_counter()
        print(f"{args.scenario} / {args.algorithm}, {sim.state.n} robots: load "
              f"{loaded - began:.3f} s, Simulation() {built - loaded:.3f} s, start() "
              f"{started - built:.3f} s")
        steps: list[tuple[float, dict[str, float]]] = []
        for _ in range(args.first_steps):
            totals.clear()
            start = time.perf_counter()
            going = sim.step()
            steps.append((time.perf_counter() - start, dict(totals)))
            if not going:
                break
    print("  step " + " ".join(f"{k + 1:>8d}" for k in range(len(steps))) + "  (ms)")
    print("  whole" + " ".join(f"{wall * 1e3:8.1f}" for wall, _ in steps))
    if len(steps) < 2:
        return
    later = steps[1:]
    labels = sorted(steps[0][1], key=lambda label: -steps[0][1][label])
    print(f"  {'phase':34s} {'step 1':>9s} {'median 2..' + str(len(steps)):>13s}")
    for label in ["whole step", *labels]:
        first = steps[0][0] if label == "whole step" else steps[0][1].get(label, 0.0)
        rest = statistics.median(wall if label == "whole step" else phases.get(label, 0.0)
                                 for wall, phases in later)
        print(f"  {label:34s} {first * 1e3:9.1f} {rest * 1e3:13.1f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_run_options(parser, scenario="cave", algorithm="deployment_team", time=60.0)
    parser.add_argument("--robots", type=int, nargs="+", default=None,
                        help="the scenario's robots parameter (default: its own); several "
                             "sizes: ns per robot-step at each")
    parser.add_argument("--runs", type=int, default=1, help="timed runs (medians)")
    parser.add_argument("--robot-logs", choices=["auto", "on", "off"], default="auto",
                        help="per-robot text logs when logging (auto: up to 200 robots)")
    parser.add_argument("--no-logging", action="store_true")
    parser.add_argument("--first-steps", type=int, default=0,
                        help="time the set-up and these first steps of one run, one by one")
    args = parser.parse_args()
    for name in STEP_PHASES:
        timed(Simulation, name, name)
    for name, module in KERNELS.items():
        timed(module, name, name)
    for name in RECORDER_HOOKS:
        timed(RunRecorder, name, "recorder." + name)
    if args.first_steps:
        first_steps(args)
        return
    logging = "off" if args.no_logging else f"on, robot logs {args.robot_logs}"
    if args.robots is None or len(args.robots) == 1:
        sim, wall, phases = measure(args, args.robots[0] if args.robots else None)
        steps = sim.state.step
        print(f"{args.scenario} / {args.algorithm}, {sim.state.n} robots, {sim.state.time:g} s "
              f"simulated, logging {logging}: {wall / steps * 1e3:.3f} ms per step, "
              f"{sim.state.time / wall:.1f} s_sim/s")
        for label, seconds in sorted(phases.items(), key=lambda item: -item[1]):
            print(f"  {label:34s} {seconds / steps * 1e3:8.3f} ms per step")
        return
    per_robot_step: dict[int, dict[str, float]] = {}
    for robots in args.robots:
        sim, wall, phases = measure(args, robots)
        robot_steps = sim.state.n * sim.state.step
        per_robot_step[robots] = {"whole step": wall / robot_steps * 1e9,
                                  **{label: seconds / robot_steps * 1e9
                                     for label, seconds in phases.items()}}
    small, large = min(args.robots), max(args.robots)
    print(f"{args.scenario} / {args.algorithm}, {args.time:g} s simulated, logging {logging}, "
          f"median of {args.runs} run(s): ns per robot-step")
    print(f"  {'phase':34s}" + "".join(f"{n:>10d}" for n in args.robots)
          + f"  {'excess at ' + str(small):>18s}")
    rows = sorted(per_robot_step[small], key=lambda label: -per_robot_step[small][label])
    for label in rows:
        costs = [per_robot_step[n].get(label, 0.0) for n in args.robots]
        excess = (per_robot_step[small][label] - per_robot_step[large].get(label, 0.0)) * small
        print(f"  {label:34s}" + "".join(f"{c:10.0f}" for c in costs)
              + f"  {excess / 1e3:11.1f} us/step")
    whole = per_robot_step[small]["whole step"] / per_robot_step[large]["whole step"]
    print(f"  whole step at {small} / at {large}: {whole:.2f}x")


if __name__ == "__main__":
    main()
