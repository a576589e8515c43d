"""The cost of the sensors' noise streams: the Cave and the Hospital (team forms), noise on
against noise off.

    python benchmarks/noise_streams.py [--time 10] [--repeats 3] [--quick] [--no-logging]
    python benchmarks/noise_streams.py --per-step [--repeats 15]

Each set-up (Cave, Hospital x noise off, "draws", on) runs in a fresh process,
in alternating order over ``--rounds`` rounds (forward, then backward...),
each giving the median of ``--repeats`` runs after a warm-up (the Cave's runs
are 6 x ``--time``). Stage's start
poses (``fixed = true``) on both sides, so that only the noise differs: the
ranger's Gaussian per beam (the built-in types' datasheet sigmas) and the
odometry's, drawn from per-sensor, per-step streams
(:mod:`mimics.engine.noise_streams`). "draws" makes every draw at a billionth
of the sigmas, so that the robots drive as without noise: its overhead is the
streams' cost; "on"'s also holds what the noise makes the robots do. Prints
s_sim/s, robot-steps/s and the overhead per step against noise off, and merges
the rows into
benchmarks/results.json under ``noise_streams``.

``--per-step`` measures in one process instead, on the states of a running team
(noise on, Stage's poses): the median time of a step (its scans read) and the
median time of adding that step's ranger noise to its scan
(:class:`~mimics.engine.noise_streams.RangerNoise`: the calling thread and a
helper thread, as in a step), and their ratio; beside it, alternating, the
noise on the calling thread alone (``numba.set_num_threads(1)``), wall and
CPU time (the CPU time of one thread is what a loaded machine does not
inflate); rows under ``noise_streams_per_step``.
"""

from __future__ import annotations

import os
import statistics
import time
from dataclasses import replace
from typing import Any

import common
import numpy as np
from common import base_spec, default_build, row_from, run_child

SCENARIOS = {"cave": "100 Pioneer2DX, 180 beams", "hospital": "2000 Swarmbots, 180 beams"}
LONGER = {"cave": 6.0, "hospital": 1.0}  # the Cave's runs are 6 x --time: its steps are short
TARGET = 0.05  # the bar: the noise streams under 5% of a step
# "draws": every draw made and added, at a billionth of the datasheet sigmas, so that the
# robots drive as without noise (real noise changes what they do: the Cave's robots that
# would come to rest go on adjusting, which costs more steps' work than the draws do)
VARIANTS = ("off", "draws", "on")


def build(spec: dict[str, Any]) -> Any:
    """The scenario; for ``draws``, with every sigma a billionth of the type's."""
    scenario = default_build(spec)
    if not spec.get("draws"):
        return scenario
    types = tuple(replace(t, ranger=replace(t.ranger, sigma=t.ranger.sigma * 1e-9),
                          odometry=replace(t.odometry,
                                           sigma_translation=t.odometry.sigma_translation * 1e-9,
                                           sigma_rotation=t.odometry.sigma_rotation * 1e-9))
                  for t in scenario.types)
    return replace(scenario, types=types)


PER_STEP_WARM = {"cave": 30, "hospital": 3}  # steps run before measuring: the team spread


def per_step(args: Any) -> None:
    """Median wall time of a step and of its ranger noise, noise on, in this process."""
    import numba

    from mimics.engine.noise_streams import RangerNoise
    from mimics.engine.simulation import Simulation

    repeats = max(args.repeats, 5)
    print(f"ranger noise per step, team deployment, noise on, medians of {repeats}")
    rows = []
    for scenario, label in SCENARIOS.items():
        scene = default_build({"scenario": scenario, "params": {"fixed": True, "noise": "on"}})
        sim = Simulation(scene, common.load_algorithm("deployment_team"), seed=1, time_limit=1e6)
        sim.start()
        for _ in range(PER_STEP_WARM[scenario]):
            sim.step()
        steps = []
        for _ in range(repeats):
            start = time.perf_counter()
            sim.step()
            steps.append(time.perf_counter() - start)
        scan, owners = sim.state.scan.copy(), sim.state.scan_hit.copy()
        noise, ids = RangerNoise(1), np.arange(sim.state.n)
        max_range, sigma = sim.types.max_range, sim.types.sigma_range
        noise.add(scan.copy(), owners, max_range, sigma, 0, ids)  # compiled or loaded
        # the noise as a step adds it (the calling thread and a helper), alternating with
        # the calling thread alone: its wall time and its CPU time (this thread's, which a
        # loaded machine does not inflate as it does the wall time)
        costs: dict[str, list[float]] = {"threads": [], "one": [], "one_cpu": []}
        threads = numba.get_num_threads()
        for k in range(repeats):
            for form in ("threads", "one") if k % 2 == 0 else ("one", "threads"):
                ranges = scan.copy()
                numba.set_num_threads(threads if form == "threads" else 1)
                cpu, start = time.thread_time(), time.perf_counter()
                noise.add(ranges, owners, max_range, sigma, k, ids)
                costs[form].append(time.perf_counter() - start)
                if form == "one":
                    costs["one_cpu"].append(time.thread_time() - cpu)
        numba.set_num_threads(threads)
        step = statistics.median(steps)
        cost, one, one_cpu = (statistics.median(costs[form])
                              for form in ("threads", "one", "one_cpu"))
        hits = float(np.mean(owners[~np.isnan(scan)] != -2))
        # on a machine busier than its cores the step waits for them and the share shrinks:
        # no verdict then (None), the figures are kept with the load they were taken under
        load = os.getloadavg()[0]
        verdict = cost / step < TARGET if load < (os.cpu_count() or 1) else None
        rows.append({"benchmark": "noise_streams_per_step", "form": f"{scenario} per step",
                     "label": label, "step_ms": 1e3 * step, "ranger_noise_ms": 1e3 * cost,
                     "share_of_step": cost / step, "ranger_noise_ms_one_thread": 1e3 * one,
                     "ranger_noise_cpu_ms_one_thread": 1e3 * one_cpu, "threads": threads,
                     "beams_hit": hits, "load_average": load, "target_met": verdict})
        print(f"  {scenario:>9} ({label}): step {1e3 * step:7.2f} ms, ranger noise "
              f"{1e3 * cost:6.3f} ms = {100 * cost / step:4.1f}% of a step on {threads} "
              f"thread(s); on one: {1e3 * one:6.3f} ms ({1e3 * one_cpu:6.3f} ms of CPU) = "
              f"{100 * one / step:4.1f}% ({100 * hits:.0f}% of beams hit; target "
              f"< {100 * TARGET:g}%{'' if verdict is not None else ': no verdict, load'} "
              f"{load:.1f})", flush=True)
    common.save_measured(args, "noise_streams_per_step", rows)


def main() -> None:
    parser = common.benchmark_parser(__doc__, time=10.0, quick_time=0.5)
    parser.add_argument("--rounds", type=int, default=2,
                        help="alternating rounds of on/off processes (default 2)")
    parser.add_argument("--per-step", action="store_true",
                        help="time a step and its ranger noise in this process instead")
    args = common.parse_or_serve_child(parser, build)
    if args is None:
        return
    if args.per_step:
        per_step(args)
        return
    print(f"noise streams, team deployment, {args.time:g} s simulated per run, median of "
          f"{args.repeats} after {args.warmup} warm-up, {args.rounds} alternating rounds, "
          f"logging {'on' if args.logging else 'off'}")
    rows = []
    for scenario, label in SCENARIOS.items():
        speeds: dict[str, list[float]] = {v: [] for v in VARIANTS}
        last: dict[str, dict] = {}
        for round_ in range(args.rounds):
            order = VARIANTS if round_ % 2 == 0 else VARIANTS[::-1]
            for variant in order:
                noise = "off" if variant == "off" else "on"
                spec = base_spec(args, algorithm="deployment_team", scenario=scenario,
                                 params={"fixed": True, "noise": noise},
                                 draws=variant == "draws")
                spec["time"] = args.time * LONGER[scenario]
                figures = run_child(__file__, spec, args.threads)
                speeds[variant].append(figures["sim_speed"])
                last[variant] = figures
        off = statistics.median(speeds["off"])
        for variant in VARIANTS:
            figures = dict(last[variant])
            figures["sim_speed"] = speed = statistics.median(speeds[variant])
            figures["robot_steps_per_s"] = (speed / 0.1) * figures["robots"]
            overhead = off / speed - 1  # extra wall time per step against noise off
            rows.append(row_from("noise_streams", f"{scenario} noise {variant}", figures,
                                 sim_speeds=speeds[variant], label=label,
                                 overhead_per_step=overhead))
            print(f"  {scenario:>9} noise {variant:>5}: {speed:8.2f} s_sim/s, "
                  f"{figures['robot_steps_per_s']:9.0f} robot-steps/s, per step "
                  f"{100 * overhead:+6.1f}% against noise off", flush=True)
        draws = off / statistics.median(speeds["draws"]) - 1
        rows[-2]["target_met"] = draws < TARGET
        print(f"  {scenario:>9} ({label}): the noise streams' draws cost {100 * draws:+.1f}% "
              f"of a step (target < {100 * TARGET:g}%: {'met' if draws < TARGET else 'NOT met'})",
              flush=True)
    common.save_measured(args, "noise_streams", rows)


if __name__ == "__main__":
    main()
