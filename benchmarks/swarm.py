"""Swarm: 100 to 10,000 e-pucks dispersing (``swarm`` scenario, ``dispersion_team``).

    python benchmarks/swarm.py [--robots 100 300 1000 3000 10000] [--time 10] [--repeats 3]
                               [--robot-logs auto|on|off] [--no-logging] [--threads N] [--quick]

Targets (issue 21, part 4; 2 cores, logging on like ``mimics run``):
10,000 robots at >= 2 s_sim/s with peak RSS under 2 GB, and the cost per
robot-step (µs) within 1.3x from 100 to 10,000 robots. The arena grows with
the team (same density). With logging on, teams of up to 200 robots also
write a text log per robot, as ``mimics run`` does (``--robot-logs auto``);
``--robot-logs off`` records the same Parquet tables at every size, and
nothing else. Each size runs in a fresh process (its own peak
RSS): one warm-up run, then the median of ``--repeats`` runs. Rows merge into
benchmarks/results.json under ``swarm`` (``swarm_robot_logs_off`` or ``_on``
with those options).
"""

from __future__ import annotations

import common

TARGET_SIM_SPEED = 2.0  # s_sim/s at 10,000 robots
TARGET_RSS_MB = 2048.0  # at 10,000 robots
TARGET_FLATNESS = 1.3  # largest / smallest µs per robot-step


def main() -> None:
    parser = common.benchmark_parser(__doc__, time=10.0, quick_time=1.0)
    common.add_run_options(parser, robots=[100, 300, 1000, 3000, 10000],
                           algorithm="dispersion_team")
    parser.add_argument("--robot-logs", choices=["auto", "on", "off"], default="auto",
                        help="per-robot text logs when logging (auto: up to 200 robots)")
    args = common.parse_or_serve_child(parser)
    if args is None:
        return
    logs = f", robot logs {args.robot_logs}" if args.logging else ""
    print(f"swarm, {args.algorithm}, {args.time:g} s simulated per run, median of "
          f"{args.repeats}, logging {'on' if args.logging else 'off'}{logs}")
    columns = ["robots", "sim_speed", "robot_steps_per_s", "us_per_robot_step", "peak_rss_mb"]
    common.print_table("", [], columns)
    rows = [common.measured_row(__file__, args, "swarm", "team", columns,
                                extra={"algorithm": args.algorithm,
                                       "robot_logs": args.robot_logs},
                                algorithm=args.algorithm, scenario="swarm",
                                params={"robots": n, "time_limit": args.time},
                                robot_logs=args.robot_logs)
            for n in args.robots]
    cost = [r["us_per_robot_step"] for r in rows]
    flatness = max(cost) / min(cost)
    largest = max(rows, key=lambda r: r["robots"])
    summary = {"flatness": flatness, "flatness_met": flatness <= TARGET_FLATNESS,
               "largest": largest["robots"],
               "sim_speed_met": largest["sim_speed"] >= TARGET_SIM_SPEED,
               "rss_met": largest["peak_rss_mb"] < TARGET_RSS_MB}
    print(f"  cost per robot-step max/min {flatness:.2f}x (target <= {TARGET_FLATNESS}); "
          f"{largest['robots']} robots: {largest['sim_speed']:.2f} s_sim/s (target >= "
          f"{TARGET_SIM_SPEED}), {largest['peak_rss_mb']:.0f} MB (target < {TARGET_RSS_MB:.0f})")
    section = "swarm" if args.robot_logs == "auto" else f"swarm_robot_logs_{args.robot_logs}"
    common.save_measured(args, section, rows, summary=summary)


if __name__ == "__main__":
    main()
