"""The Cave as a PettingZoo environment: environment steps per second with random actions.

    python benchmarks/env_steps.py [--steps 100] [--repeats 5] [--threads 1 2]
                                   [--observation dict flat] [--quick]

Bar (issue 17): >= 1,000 environment steps per second for the Cave (100
Pioneer2DX, 180-beam 8 m lasers), logging off. Each row runs in a fresh
process (``NUMBA_NUM_THREADS`` per row): one warm-up episode, then
``--repeats`` episodes of ``--steps`` steps, each from ``reset(seed=k)``.
Every step draws random actions for the live agents (uniform over their
action boxes, one NumPy call for all of them, into the actions dict a
training loop would build) and calls ``env.step``; that whole loop is
timed, resets apart. Printed per row: median env steps/s, median
robot-steps/s (live agents summed over the steps, per second), the mean
number of live agents (random actions crash robots, which then leave the
episode and the world gets cheaper: read the steps/s with it), and the
median reset time. Also the steps per CPU-second of the process (all its
threads): on a machine shared with other busy processes, wall-clock figures
fall with the load, while CPU time counts only the work done; with one
thread, steps per CPU-second is about what an idle machine gives per
wall-clock second.

The ``engine`` rows run the same random references through the engine alone
(a team algorithm, ``Simulation.step()`` in a loop, same seeds): the
difference is what the environment layer costs per step.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np
from common import RESULTS, add_run_options, print_table, run_child, save

SCENARIO = "cave"
BAR = 1000.0  # env steps per second


def _random_actions(rng: np.random.Generator, low: np.ndarray, high: np.ndarray) -> np.ndarray:
    return rng.uniform(low, high).astype(np.float32)


def measure_env(observation: str, steps: int, repeats: int) -> dict[str, Any]:
    """Time ``repeats`` episodes of ``steps`` env steps (plus one warm-up)."""
    import mimics.env

    env = mimics.env.parallel_env(SCENARIO, observation=observation)
    names = env.possible_agents
    low = np.array([env.action_space(a).low for a in names], dtype=np.float64)
    high = np.array([env.action_space(a).high for a in names], dtype=np.float64)
    row_of = {a: k for k, a in enumerate(names)}
    speeds, cpu_speeds, robot_speeds, live_means, resets = [], [], [], [], []
    for episode in range(repeats + 1):
        rng = np.random.default_rng(episode)
        began = time.perf_counter()
        env.reset(seed=episode)
        reset_time = time.perf_counter() - began
        live_total = 0
        done = 0
        began, cpu_began = time.perf_counter(), time.process_time()
        while done < steps and env.agents:
            agents = env.agents
            rows = [row_of[a] for a in agents]
            actions = dict(zip(agents, _random_actions(rng, low[rows], high[rows]), strict=True))
            live_total += len(agents)
            env.step(actions)
            done += 1
        elapsed, cpu = time.perf_counter() - began, time.process_time() - cpu_began
        if episode == 0:
            continue  # warm-up: caches, first-touch of the arrays
        speeds.append(done / elapsed)
        cpu_speeds.append(done / cpu)
        robot_speeds.append(live_total / elapsed)
        live_means.append(live_total / done)
        resets.append(reset_time)
    env.close()
    return _figures(speeds, cpu_speeds, robot_speeds, live_means, resets)


def measure_engine(steps: int, repeats: int) -> dict[str, Any]:
    """The same random references through the engine alone (no environment layer)."""
    from mimics.catalog import load_scenario
    from mimics.engine.user_code import TeamController
    from mimics.records.runner import prepare

    scenario = load_scenario(SCENARIO)
    max_speed = np.array([scenario.robot_type(i).max_speed for i in range(scenario.robot_count)])
    speeds, cpu_speeds, robot_speeds, live_means, resets = [], [], [], [], []
    for episode in range(repeats + 1):
        rng = np.random.default_rng(episode)

        def team_step(team: Any, rng: np.random.Generator = rng) -> tuple[Any, Any]:
            top = max_speed[team.ids]
            turn = rng.uniform(-np.pi, np.pi, len(team.ids))
            return rng.uniform(-top, top), team.pose[:, 2] + turn

        began = time.perf_counter()
        sim = prepare(scenario, TeamController("random", team_step=team_step), seed=episode)
        sim.start()
        reset_time = time.perf_counter() - began
        live_total = done = 0
        began, cpu_began = time.perf_counter(), time.process_time()
        while done < steps and sim.status == "running":
            live_total += int(np.count_nonzero(sim.state.active))
            sim.step()
            done += 1
        elapsed, cpu = time.perf_counter() - began, time.process_time() - cpu_began
        if episode == 0:
            continue
        speeds.append(done / elapsed)
        cpu_speeds.append(done / cpu)
        robot_speeds.append(live_total / elapsed)
        live_means.append(live_total / done)
        resets.append(reset_time)
    return _figures(speeds, cpu_speeds, robot_speeds, live_means, resets)


def _figures(speeds: list[float], cpu_speeds: list[float], robot_speeds: list[float],
             live: list[float], resets: list[float]) -> dict[str, Any]:
    import numba

    return {"env_steps_per_s": statistics.median(speeds),
            "env_steps_per_cpu_s": statistics.median(cpu_speeds),
            "robot_steps_per_s": statistics.median(robot_speeds),
            "mean_live_agents": statistics.mean(live),
            "reset_ms": 1000 * statistics.median(resets),
            "runs_env_steps_per_s": [round(s, 1) for s in speeds],
            "threads": numba.get_num_threads()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=100, help="env steps per episode")
    parser.add_argument("--repeats", type=int, default=5, help="timed episodes per row")
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--observation", nargs="+", default=["dict", "flat"])
    parser.add_argument("--quick", action="store_true", help="20 steps, 2 repeats")
    add_run_options(parser, results=RESULTS)
    parser.add_argument("--child", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        spec = json.loads(args.child)
        if spec["form"] == "engine":
            figures = measure_engine(spec["steps"], spec["repeats"])
        else:
            figures = measure_env(spec["form"], spec["steps"], spec["repeats"])
        print(json.dumps(figures))
        return
    if args.quick:
        args.steps, args.repeats = 20, 2
    rows = []
    for threads in args.threads:
        for form in ["engine", *args.observation]:
            spec = {"form": form, "steps": args.steps, "repeats": args.repeats}
            figures = run_child(Path(__file__), spec, threads=threads)
            rows.append({"form": form if form == "engine" else f"env {form}", **figures,
                         "meets_bar": form == "engine" or figures["env_steps_per_s"] >= BAR})
            print_table("" if len(rows) > 1 else
                        f"Cave, 100 robots, 180 beams, random actions, {args.steps} steps "
                        f"per episode, logging off", rows[-1:],
                        ["form", "threads", "env_steps_per_s", "env_steps_per_cpu_s",
                         "robot_steps_per_s",
                         "mean_live_agents", "reset_ms", "meets_bar"], header=len(rows) == 1)
            print("    single runs:", figures["runs_env_steps_per_s"], flush=True)
    save("env_steps", {"scenario": SCENARIO, "steps": args.steps, "repeats": args.repeats,
                       "python": sys.version.split()[0], "rows": rows}, args.results)


if __name__ == "__main__":
    main()
