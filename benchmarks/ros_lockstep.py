"""The speed of a lockstep ROS run: the rospy example driving the line's robots.

    python benchmarks/ros_lockstep.py [--robots 5] [--repeats 3]

Starts a ``rosmaster`` on a free port, then, ``--repeats`` times, the example
node ``examples/ros/go_to_goal_node.py`` (with the system's Python) beside
``mimics ros line --robots N --lockstep``. Each run is timed by its own
summary (wall time of the simulation, not of the process start), so the
figures are s_sim/s and robot-steps/s of the simulation with its ROS round
trips. Prints each run and the medians. Needs ROS 1 (see docs/how-to/ros.md).
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

EXAMPLE = Path(__file__).parents[1] / "examples" / "ros" / "go_to_goal_node.py"


def free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def one_run(env: dict[str, str], robots: int, folder: Path) -> dict:
    node = subprocess.Popen(["/usr/bin/python3", str(EXAMPLE), "--robots", str(robots)],
                            env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        subprocess.run([sys.executable, "-m", "mimics", "ros", "line", "--robots", str(robots),
                        "--lockstep", "--out", str(folder), "--robot-logs", "off"],
                       env=env, check=True, stdout=subprocess.DEVNULL)
    finally:
        node.send_signal(signal.SIGINT)
        node.wait(15)
    return json.loads((folder / "summary.json").read_text())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--robots", type=int, default=5)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    port = free_port()
    env = {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{port}", "ROS_IP": "127.0.0.1"}
    master = subprocess.Popen(["rosmaster", "--core", "-p", str(port)], env=env,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(1.0)
        speeds, rates = [], []
        with tempfile.TemporaryDirectory() as root:
            for k in range(args.repeats):
                summary = one_run(env, args.robots, Path(root) / f"run{k}")
                speed = summary["sim_time"] / summary["wall_time"]
                rate = summary["steps"] * args.robots / summary["wall_time"]
                speeds.append(speed)
                rates.append(rate)
                print(f"run {k}: {summary['reached_goal']}/{args.robots} reached, "
                      f"{summary['sim_time']:.1f} s_sim in {summary['wall_time']:.2f} s: "
                      f"{speed:.1f} s_sim/s, {rate:.0f} robot-steps/s", flush=True)
        print(f"median: {statistics.median(speeds):.1f} s_sim/s, "
              f"{statistics.median(rates):.0f} robot-steps/s "
              f"({args.robots} robots, lockstep)")
    finally:
        master.terminate()
        master.wait(10)


if __name__ == "__main__":
    main()
