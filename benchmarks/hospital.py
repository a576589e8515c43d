"""Stage's Hospital: 2,000 robots of 0.1 m (LMS200, 180 beams, 2 m), ``deployment(_team)``.

    python benchmarks/hospital.py [--time 10] [--repeats 3] [--no-logging] [--threads N] [--quick]

Targets (issue: 2 cores, no live view, logging on, collisions on): per-robot
``deployment`` >= 0.5 s_sim/s, team ``deployment_team`` >= 2 s_sim/s. Each
form runs in a fresh process (its own peak RSS): one short warm-up run, then
the median of ``--repeats`` runs of ``--time`` simulated seconds, each
recorded like ``mimics run`` into a temporary run folder (unless
``--no-logging``). Prints one row per form and merges them into
benchmarks/results.json under ``hospital``.
"""

from __future__ import annotations

import argparse

from common import add_common_arguments, child_main, form_rows, meta, resolve, save

TARGETS = {"per-robot": 0.5, "team": 2.0}  # s_sim/s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_common_arguments(parser, time=10.0, quick_time=0.5)
    args = resolve(parser.parse_args())
    if args.child:
        child_main(args.child)
        return
    print(f"hospital, 2000 robots, {args.time:g} s simulated per run, median of "
          f"{args.repeats} after {args.warmup} warm-up of {args.warmup_time:g} s, "
          f"logging {'on' if args.logging else 'off'}")
    rows = form_rows(__file__, "hospital", args,
                     {"per-robot": "deployment", "team": "deployment_team"}, scenario="hospital")
    for row in rows:
        row["target_sim_speed"] = TARGETS[row["form"]]
        row["target_met"] = row["sim_speed"] >= TARGETS[row["form"]]
        print(f"  {row['form']:>9}: {row['sim_speed']:.2f} s_sim/s, target >= "
              f"{row['target_sim_speed']:g}: {'met' if row['target_met'] else 'NOT met'}")
    save("hospital", {"meta": meta(args), "rows": rows}, args.results)


if __name__ == "__main__":
    main()
