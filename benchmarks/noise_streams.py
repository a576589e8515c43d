"""The cost of the sensors' noise streams: the Cave and the Hospital (team forms), noise on
against noise off.

    python benchmarks/noise_streams.py [--time 10] [--repeats 3] [--quick] [--no-logging]

Each of the four set-ups (Cave, Hospital x noise on, off) runs in a fresh
process, in alternating order over ``--rounds`` rounds (on, off, off, on...),
each giving the median of ``--repeats`` runs after a warm-up (the Cave's runs
are 6 x ``--time``). Stage's start
poses (``fixed = true``) on both sides, so that only the noise differs: the
ranger's Gaussian per beam (the built-in types' datasheet sigmas) and the
odometry's, drawn from per-sensor, per-step streams
(:mod:`mimics.engine.noise_streams`). Prints s_sim/s, robot-steps/s and the
overhead of noise per step (on / off - 1), and merges the rows into
benchmarks/results.json under ``noise_streams``.
"""

from __future__ import annotations

import statistics

from common import base_spec, benchmark_parser, meta, parse_or_serve_child, row_from, run_child
from common import save as save_section

SCENARIOS = {"cave": "100 Pioneer2DX, 180 beams", "hospital": "2000 Swarmbots, 180 beams"}
LONGER = {"cave": 6.0, "hospital": 1.0}  # the Cave's runs are 6 x --time: its steps are short
TARGET = 0.05  # the bar: the noise streams under 5% of a step


def main() -> None:
    parser = benchmark_parser(__doc__, time=10.0, quick_time=0.5)
    parser.add_argument("--rounds", type=int, default=2,
                        help="alternating rounds of on/off processes (default 2)")
    args = parse_or_serve_child(parser)
    if args is None:
        return
    print(f"noise streams, team deployment, {args.time:g} s simulated per run, median of "
          f"{args.repeats} after {args.warmup} warm-up, {args.rounds} alternating rounds, "
          f"logging {'on' if args.logging else 'off'}")
    rows = []
    for scenario, label in SCENARIOS.items():
        speeds: dict[str, list[float]] = {"on": [], "off": []}
        last: dict[str, dict] = {}
        for round_ in range(args.rounds):
            order = ("on", "off") if round_ % 2 == 0 else ("off", "on")
            for noise in order:
                spec = base_spec(args, algorithm="deployment_team", scenario=scenario,
                                 params={"fixed": True, "noise": noise})
                spec["time"] = args.time * LONGER[scenario]
                figures = run_child(__file__, spec, args.threads)
                speeds[noise].append(figures["sim_speed"])
                last[noise] = figures
        for noise in ("off", "on"):
            figures = dict(last[noise])
            figures["sim_speed"] = statistics.median(speeds[noise])
            figures["robot_steps_per_s"] = (figures["sim_speed"] / 0.1) * figures["robots"]
            rows.append(row_from("noise_streams", f"{scenario} noise {noise}", figures,
                                 sim_speeds=speeds[noise], label=label))
        on, off = statistics.median(speeds["on"]), statistics.median(speeds["off"])
        overhead = off / on - 1  # extra wall time per step with noise
        rows[-1]["overhead_per_step"] = overhead
        rows[-1]["target_met"] = overhead < TARGET
        print(f"  {scenario:>9} ({label}): noise off {off:.2f} s_sim/s "
              f"({off * 10 * last['off']['robots']:.0f} robot-steps/s), on {on:.2f} s_sim/s "
              f"({on * 10 * last['on']['robots']:.0f} robot-steps/s): noise costs "
              f"{100 * overhead:+.1f}% of a step (target < {100 * TARGET:g}%: "
              f"{'met' if overhead < TARGET else 'NOT met'})", flush=True)
    save_section("noise_streams", {"meta": meta(args), "rows": rows}, args.results)


if __name__ == "__main__":
    main()
