"""What a C step costs against a Python one: deployment in the Cave, 100 robots.

    python benchmarks/c_step.py [--time 20] [--repeats 5] [--threads 1] [--quick]

Four forms of the same behaviour, run one after another in each round, in
one fresh process (after a warm-up of each), so that they see the same
machine: ``deployment`` (Python, one call per robot), ``deployment_team``
(Python, one NumPy call per step), ``examples/c/deployment.c`` (C, one call
per robot, all of a step in one call into C) and ``still`` (a team step that
leaves every robot where it is: the engine's own cost, robots not moving).
Printed per form, medians over the rounds:

* whole runs: s_sim/s, robot-steps/s, µs per robot-step (wall) and CPU µs per
  robot-step (process CPU time: less blurred than wall time on a busy machine);
* µs per call: the controller alone, the world frozen after 5 s of the run:
  ``compute()`` for all robots called again and again, its wall time divided
  by the robots (adapter, conversions and the engine's own timing included);
* inside: the engine's clock around each call (team form: a call's time
  divided by the robots).

Deadlock deactivation is off, so that every robot stays active and every
form drives the same number of robots. The C file is compiled (or found in
the cache) before timing. Runs are not recorded. Merges the figures into
benchmarks/results.json under ``c_step``.
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path
from typing import Any

import numpy as np
from common import benchmark_parser, parse_or_serve_child, run_child, save_measured, time_runs

C_DEPLOYMENT = Path(__file__).resolve().parents[1] / "examples" / "c" / "deployment.c"
FORMS = ("still", "deployment", "deployment_team", "deployment.c")


class Still:
    """Every robot stays where it is, the whole team in one call: the engine alone."""

    def team_step(self, team: Any) -> tuple[np.ndarray, np.ndarray]:
        """Zero speed and the current headings."""
        pose = team.pose
        return np.zeros(len(pose)), np.array(pose[:, 2])


def child(spec: dict[str, Any]) -> dict[str, list[dict[str, float]]]:
    """Warm up each form, then ``repeats`` rounds of all of them; per-round figures."""
    from mimics.catalog import find_algorithm, load_scenario
    from mimics.engine.simulation import Simulation

    scenario = load_scenario("cave").with_settings(deactivate_on_deadlock=False)
    algorithms: dict[str, Any] = {"still": Still,
                                  "deployment": find_algorithm("deployment")[1],
                                  "deployment_team": find_algorithm("deployment_team")[1]}
    made: list[Simulation] = []

    def make(name: str, limit: float) -> Any:
        def build() -> Simulation:
            # the C form: a fresh controller per simulation, as `prepare` makes
            algorithm = (find_algorithm(str(C_DEPLOYMENT))[1] if name == "deployment.c"
                         else algorithms[name])
            made.append(Simulation(scenario, algorithm, seed=1, time_limit=limit,
                                   algorithm_name=name))
            return made[-1]
        return build

    for name in FORMS:
        time_runs(make(name, spec["warmup_time"]), repeats=1, warmup=0, min_seconds=0.0)
    frozen = {name: _frozen_world(make(name, 5.0)) for name in FORMS}
    rounds: dict[str, list[dict[str, float]]] = {name: [] for name in FORMS}
    for _ in range(spec["repeats"]):
        for name in FORMS:
            figures = time_runs(make(name, spec["time"]), repeats=1, warmup=0, min_seconds=0.0)
            sim = made[-1]
            robot_steps = max(figures["robot_steps"], 1)
            rounds[name].append({
                "sim_speed": figures["sim_speed"],
                "robot_steps_per_s": figures["robot_steps_per_s"],
                "us_per_robot_step": figures["us_per_robot_step"],
                "cpu_us_per_robot_step": 1e6 * figures["cpu_time"] / robot_steps,
                "us_per_call": _controller_us_per_call(frozen[name], spec["calls"]),
                "inside_us_per_call": 1e6 * sim.timing.total / max(sim.timing.count, 1),
                "robots": figures["robots"], "steps": figures["steps"],
                "load_average": figures["load_average_after"], "threads": figures["threads"]})
    return rounds


def _frozen_world(make: Any) -> Any:
    """A simulation run to its time limit, its controller ready to compute again."""
    sim = make()
    sim.run()
    return sim


def _controller_us_per_call(sim: Any, calls: int) -> float:
    """Median wall time of ``compute()`` for all robots, per robot (µs), the world frozen."""
    ids = np.arange(sim.state.n)
    times = []
    for _ in range(calls):
        start = time.perf_counter()
        sim.controller.compute(sim, ids)
        times.append(time.perf_counter() - start)
    return 1e6 * statistics.median(times) / len(ids)


def main() -> None:
    parser = benchmark_parser(__doc__, time=20.0, quick_time=2.0, repeats=5, quick_repeats=2)
    parser.set_defaults(logging=False)
    args = parse_or_serve_child(parser, child=child)
    if args is None:
        return
    spec = {"time": args.time, "warmup_time": args.warmup_time, "repeats": args.repeats,
            "calls": 20 if args.quick else 100}
    rounds = run_child(__file__, spec, args.threads)
    base = rounds["still"]
    robots = base[0]["robots"]
    print(f"cave, {robots} robots, {args.time:g} s simulated ({base[0]['steps']} steps) per run, "
          f"median of {args.repeats} rounds, {base[0]['threads']} numba thread(s), not recorded; "
          f"load average {statistics.median(r['load_average'] for r in base):.1f} "
          "(a shared machine: figures are noisy)")
    print(f"  {'form':>16} {'s_sim/s':>9} {'robot-steps/s':>14} {'us/robot-step':>14} "
          f"{'CPU us/r-s':>11} {'us/call':>9} {'inside':>9}")
    rows: list[dict[str, Any]] = []
    keys = ("sim_speed", "robot_steps_per_s", "us_per_robot_step", "cpu_us_per_robot_step",
            "us_per_call", "inside_us_per_call")
    for name in FORMS:
        mine = rounds[name]
        row = {"benchmark": "c_step", "form": name, "scenario": "cave", "robots": robots,
               "sim_time": args.time, **{key: statistics.median(r[key] for r in mine)
                                         for key in keys}, "threads": mine[0]["threads"]}
        rows.append(row)
        print(f"  {name:>16} {row['sim_speed']:9.2f} {row['robot_steps_per_s']:14.0f} "
              f"{row['us_per_robot_step']:14.2f} {row['cpu_us_per_robot_step']:11.2f} "
              f"{row['us_per_call']:9.3f} {row['inside_us_per_call']:9.3f}")
    print("  us/call: the controller alone (world frozen), per robot; inside: the engine's "
          "clock around each call (team: per robot); CPU us/r-s: process CPU per robot-step")
    save_measured(args, "c_step", rows, rounds=rounds)


if __name__ == "__main__":
    main()
