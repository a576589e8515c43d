"""Both cores: the Cave (team form) with NUMBA_NUM_THREADS=1 and 2; speedup and determinism.

    python benchmarks/threads.py [--threads-list 1 2] [--time 60] [--repeats 3]
                                 [--algorithm deployment_team] [--no-logging] [--quick]

Each thread count runs in a fresh process with ``NUMBA_NUM_THREADS`` set
(recorded like ``mimics run`` unless ``--no-logging``; median of
``--repeats`` runs after a short warm-up). Prints s_sim/s per thread count,
the speedup of each over the first, and whether the final states are
bit-identical: SHA-256 of the final pose and scan arrays of the same seeded
run. Merges the figures into benchmarks/results.json under ``threads``.
"""

from __future__ import annotations

import common


def main() -> None:
    parser = common.benchmark_parser(__doc__, time=60.0, quick_time=5.0)
    parser.add_argument("--threads-list", type=int, nargs="+", default=[1, 2])
    common.add_run_options(parser, scenario="cave", algorithm="deployment_team")
    args = common.parse_or_serve_child(parser)
    if args is None:
        return
    print(f"{args.scenario} / {args.algorithm}, {args.time:g} s simulated per run, median of "
          f"{args.repeats}, logging {'on' if args.logging else 'off'}, NUMBA_NUM_THREADS "
          f"{args.threads_list}")
    common.print_table("", [], common.TABLE_COLUMNS)
    form = "team" if args.algorithm.endswith("_team") else "per-robot"
    rows = [common.measured_row(__file__, args, args.scenario, form, common.TABLE_COLUMNS,
                                threads, {"algorithm": args.algorithm,
                                          "threads_requested": threads},
                                algorithm=args.algorithm, scenario=args.scenario)
            for threads in args.threads_list]
    base = rows[0]
    for row in rows:
        row["speedup"] = row["sim_speed"] / base["sim_speed"]
        row["identical_to_first"] = row["hashes"] == base["hashes"]
    for row in rows[1:]:
        print(f"  speedup {base['threads']} -> {row['threads']} threads: {row['speedup']:.2f}x")
    for row in rows:
        print(f"  {row['threads']} thread(s): pose {row['hashes']['pose'][:16]}  "
              f"scan {row['hashes']['scan'][:16]}")
    identical = all(row["identical_to_first"] for row in rows)
    print(f"  final pose and scan arrays bit-identical across thread counts: "
          f"{'yes' if identical else 'NO'}")
    if any(row["threads"] != row["threads_requested"] for row in rows):
        print("  warning: numba ran with a different thread count than requested "
              "(more threads than cores?)")
    common.save_measured(args, "threads", rows, identical=identical,
                         speedup=rows[-1]["speedup"])


if __name__ == "__main__":
    main()
