"""The paper's line scenario at growing team sizes: is the cost per robot-step flat?

    python benchmarks/line_scaling.py [--robots 1 10 60 100 300 1000] [--repeats 3]
                                      [--results benchmarks/results.json]

Prints s_sim/s and robot-steps/s for the per-robot and team ``go_to_goal``.
"""

from __future__ import annotations

import argparse

from common import RESULTS, add_run_options, print_table, save, time_runs

from mimics.algorithms import go_to_goal, go_to_goal_team
from mimics.engine.simulation import Simulation
from mimics.scenarios.line import scenario


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    add_run_options(parser, robots=[1, 10, 60, 100, 300, 1000], repeats=3, time=21.8,
                    results=RESULTS)
    args = parser.parse_args()
    rows = []
    for form, algorithm in (("per-robot", go_to_goal), ("team", go_to_goal_team)):
        for n in args.robots:
            scen = scenario(robots=n)
            figures = time_runs(lambda s=scen, a=algorithm: Simulation(s, a, seed=1,
                                                                       time_limit=args.time),
                                repeats=args.repeats)
            figures["us_per_robot_step"] = 1e6 / figures["robot_steps_per_s"]
            rows.append({"benchmark": "line", "form": form, **figures})
            print_table("", [rows[-1]], ["form", "robots", "sim_speed", "robot_steps_per_s",
                                         "us_per_robot_step", "rays_per_s", "peak_rss_mb"])
    save("line_scaling", rows, args.results)


if __name__ == "__main__":
    main()
