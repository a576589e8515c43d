"""Stage's Cave: 100 Pioneer2DX (LMS200, 180 beams, 8 m), ``deployment`` and ``deployment_team``.

    python benchmarks/cave.py [--time 60] [--repeats 3] [--no-logging] [--threads N] [--quick]

Targets (issue: 2 cores, no live view, logging on, collisions on): per-robot
``deployment`` >= 20 s_sim/s, team ``deployment_team`` >= 100 s_sim/s. Each
form runs in a fresh process (its own peak RSS): one short warm-up run, then
the median of ``--repeats`` runs of ``--time`` simulated seconds, each
recorded like ``mimics run`` into a temporary run folder (unless
``--no-logging``). Prints one row per form and merges them into
benchmarks/results.json under ``cave``.
"""

from __future__ import annotations

import argparse

from common import add_common_arguments, child_main, form_rows, meta, resolve, save

TARGETS = {"per-robot": 20.0, "team": 100.0}  # s_sim/s


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_common_arguments(parser, time=60.0, quick_time=5.0)
    args = resolve(parser.parse_args())
    if args.child:
        child_main(args.child)
        return
    print(f"cave, 100 Pioneer2DX, {args.time:g} s simulated per run, median of "
          f"{args.repeats} after {args.warmup} warm-up of {args.warmup_time:g} s, "
          f"logging {'on' if args.logging else 'off'}")
    rows = form_rows(__file__, "cave", args,
                     {"per-robot": "deployment", "team": "deployment_team"}, scenario="cave")
    for row in rows:
        row["target_sim_speed"] = TARGETS[row["form"]]
        row["target_met"] = row["sim_speed"] >= TARGETS[row["form"]]
        print(f"  {row['form']:>9}: {row['sim_speed']:.2f} s_sim/s, target >= "
              f"{row['target_sim_speed']:g}: {'met' if row['target_met'] else 'NOT met'}")
    save("cave", {"meta": meta(args), "rows": rows}, args.results)


if __name__ == "__main__":
    main()
