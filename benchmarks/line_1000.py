"""The paper's line at 10 and 1,000 Pioneer3AT (270 beams, 30 m): is a robot-step as cheap?

    python benchmarks/line_1000.py [--robots 10 1000] [--time 21.8] [--repeats 3]
                                   [--no-logging] [--threads N] [--quick]

Target (issue): with 1,000 robots, robot-steps/s within 2x of the 10-robot
figure, for ``go_to_goal`` (per-robot) and ``go_to_goal_team`` (team). Each
row runs in a fresh process (its own peak RSS), recorded like ``mimics run``
unless ``--no-logging``; median of ``--repeats`` runs after a short warm-up.
Prints the rows and, per form, the ratio of robot-steps/s at the largest team
to the smallest; merges them into benchmarks/results.json under ``line_1000``.
"""

from __future__ import annotations

import common

FORMS = {"per-robot": "go_to_goal", "team": "go_to_goal_team"}
TARGET_RATIO = 0.5  # robot-steps/s at 1,000 robots over that at 10: within 2x


def main() -> None:
    parser = common.benchmark_parser(__doc__, time=21.8, quick_time=2.0)
    common.add_run_options(parser, robots=[10, 1000])
    args = common.parse_or_serve_child(parser)
    if args is None:
        return
    print(f"line, robots {args.robots}, {args.time:g} s simulated per run (all reach their goals "
          f"by 21.8 s), median of {args.repeats}, logging {'on' if args.logging else 'off'}")
    common.print_table("", [], common.TABLE_COLUMNS)
    rows = [common.measured_row(__file__, args, "line", form, common.TABLE_COLUMNS,
                                extra={"algorithm": algorithm}, algorithm=algorithm,
                                scenario="line", params={"robots": n})
            for form, algorithm in FORMS.items() for n in args.robots]
    ratios = []
    for form in FORMS:
        mine = sorted((r for r in rows if r["form"] == form), key=lambda r: r["robots"])
        small, big = mine[0], mine[-1]
        ratio = big["robot_steps_per_s"] / small["robot_steps_per_s"]
        ratios.append({"benchmark": "line", "form": form, "robots_small": small["robots"],
                       "robots_big": big["robots"], "ratio": ratio, "target": TARGET_RATIO,
                       "target_met": ratio >= TARGET_RATIO})
        print(f"  {form:>9}: robot-steps/s at {big['robots']} / at {small['robots']} = "
              f"{ratio:.2f} (target >= {TARGET_RATIO:g}, within 2x): "
              f"{'met' if ratio >= TARGET_RATIO else 'NOT met'}")
    common.save_measured(args, "line_1000", rows, ratios=ratios)


if __name__ == "__main__":
    main()
