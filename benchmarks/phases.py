"""Where a step goes: wall time of each phase of the step, per step, over one run.

    python benchmarks/phases.py [--scenario cave] [--algorithm deployment_team]
                                [--time 60] [--robots N] [--no-logging]

Wraps the step's phases (the ``Simulation`` methods a step calls, the kernels
it calls and the recorder's hooks) in wall-clock timers, runs the scenario
once to warm up and once timed, and prints milliseconds per step for each,
largest first. Phases nest (``_sense`` holds ``trace_beams``), so the column
does not add up to the total. Unlike the other benchmarks this one reaches
into the engine's private methods: it is a profiler, its names may change
with the engine.
"""

from __future__ import annotations

import argparse
import collections
import tempfile
import time
from collections.abc import Callable
from typing import Any

import mimics.engine.scanner as scanner_module
import mimics.engine.simulation as simulation_module
import mimics.engine.step_checks as step_checks_module
from mimics.catalog import find_algorithm, load_scenario
from mimics.engine.simulation import Simulation
from mimics.records.recorder import RunRecorder

STEP_PHASES = ["_move", "_check_moved", "_mark_departures_and_arrivals", "_check_stalls",
               "_finish_deactivations", "_sense", "_robot_index", "_check_end",
               "_handle_failures"]
# each kernel in the module that calls it (where the wrapper must replace it)
KERNELS = {"trace_beams": scanner_module, "measure_positioning": simulation_module,
           "_check_kernel": step_checks_module, "index_robots": simulation_module,
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenario", default="cave")
    parser.add_argument("--algorithm", default="deployment_team")
    parser.add_argument("--time", type=float, default=60.0)
    parser.add_argument("--robots", type=int, default=None,
                        help="the scenario's robots parameter (default: its own)")
    parser.add_argument("--no-logging", action="store_true")
    args = parser.parse_args()
    for name in STEP_PHASES:
        timed(Simulation, name, name)
    for name, module in KERNELS.items():
        timed(module, name, name)
    for name in RECORDER_HOOKS:
        timed(RunRecorder, name, "recorder." + name)
    algorithm = find_algorithm(args.algorithm)[1]
    for _run in ("warm-up", "timed"):  # the last one is reported
        params = {} if args.robots is None else {"robots": args.robots}
        sim = Simulation(load_scenario(args.scenario, **params), algorithm, seed=1,
                         time_limit=args.time)
        with tempfile.TemporaryDirectory(prefix="mimics-phases-") as folder:
            if not args.no_logging:
                sim.observers.append(RunRecorder(folder))
            timed(sim.controller, "compute", "algorithm (controller.compute)")
            sim.start()
            totals.clear()
            start = time.perf_counter()
            while sim.step():
                pass
            wall = time.perf_counter() - start
    steps = sim.state.step
    print(f"{args.scenario} / {args.algorithm}, {sim.state.n} robots, {sim.state.time:g} s "
          f"simulated, logging {'off' if args.no_logging else 'on'}: "
          f"{wall / steps * 1e3:.3f} ms per step, {sim.state.time / wall:.1f} s_sim/s")
    for label, seconds in sorted(totals.items(), key=lambda item: -item[1]):
        print(f"  {label:34s} {seconds / steps * 1e3:8.3f} ms per step")


if __name__ == "__main__":
    main()
