"""The speed of a lockstep ROS run: the rospy example driving the line's robots.

    python benchmarks/ros_lockstep.py [--robots 4 20 100] [--repeats 3]

Starts a ``rosmaster`` on a free port, then, for each robot count, ``--repeats``
times, the example node ``examples/ros/go_to_goal_node.py`` (with the
system's Python) beside ``mimics ros line --robots N --lockstep`` (the counts
alternate run by run, so a change of the machine's load touches them all).
Each run is timed by its own summary (wall time of the simulation, not of the
process start), so the figures are s_sim/s and robot-steps/s of the
simulation with its ROS round trips. Prints each run, then a table of the
medians per robot count. Needs ROS 1 (see docs/how-to/ros.md).
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import add_run_options, speeds_text

EXAMPLE = Path(__file__).parents[1] / "examples" / "ros" / "go_to_goal_node.py"


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def one_run(env: dict[str, str], robots: int, folder: Path) -> dict:
    node = subprocess.Popen(["/usr/bin/python3", str(EXAMPLE), "--robots", str(robots)],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        # a long connection time-out: 100 robots' subscriptions take a while on a busy machine
        subprocess.run([sys.executable, "-m", "mimics", "ros", "line", "--robots", str(robots),
                        "--lockstep", "--out", str(folder), "--robot-logs", "off",
                        "--timeout", "60"],
                       env=env, check=True, stdout=subprocess.DEVNULL)
    finally:
        node.send_signal(signal.SIGINT)
        node.wait(15)
    return json.loads((folder / "summary.json").read_text())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_run_options(parser, robots=[4, 20, 100], repeats=3)
    args = parser.parse_args()
    port = free_port()
    env = {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{port}", "ROS_IP": "127.0.0.1"}
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(1.0)
        speeds: dict[int, list[float]] = {n: [] for n in args.robots}
        rates: dict[int, list[float]] = {n: [] for n in args.robots}
        with tempfile.TemporaryDirectory() as root:
            for k in range(args.repeats):
                for robots in args.robots:
                    summary = one_run(env, robots, Path(root) / f"run{robots}-{k}")
                    speed = summary["sim_time"] / summary["wall_time"]
                    rate = summary["steps"] * robots / summary["wall_time"]
                    speeds[robots].append(speed)
                    rates[robots].append(rate)
                    print(f"{robots} robots, run {k}: {summary['reached_goal']}/{robots} "
                          f"reached, {summary['sim_time']:.1f} s_sim in "
                          f"{summary['wall_time']:.2f} s: {speeds_text(speed, rate, 1)}",
                          flush=True)
        print(f"\nlockstep, medians of {args.repeats} (min to max):")
        print("| robots | s_sim/s | robot-steps/s |")
        print("|---|---|---|")
        for robots in args.robots:
            low, high = min(speeds[robots]), max(speeds[robots])
            print(f"| {robots} | {statistics.median(speeds[robots]):.1f} ({low:.1f} to "
                  f"{high:.1f}) | {statistics.median(rates[robots]):,.0f} |")
    finally:
        master.terminate()
        master.wait(10)


if __name__ == "__main__":
    main()
