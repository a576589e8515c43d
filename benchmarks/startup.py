"""How long a cached ``mimics run`` takes to reach and finish its first step.

    python benchmarks/startup.py [--repeats 3]

Runs ``mimics run line go_to_goal --robots 60 --time 0.1`` (one step, logging
on) in fresh processes: a warm-up (which fills Numba's on-disk cache if it is
empty), then ``--repeats`` timed runs. The wall time of the whole command,
start-up to exit, bounds the time to the first step from above. The issue's
bar: within 3 s once the cache is warm. Merges the figures into
benchmarks/results.json under ``startup``.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import save

COMMAND = ["run", "line", "go_to_goal", "--robots", "60", "--time", "0.1", "--seed", "1"]


def one_run(folder: Path) -> float:
    """Wall seconds of one ``mimics run`` in a fresh interpreter."""
    out = folder / "run"
    shutil.rmtree(out, ignore_errors=True)
    began = time.perf_counter()
    subprocess.run([sys.executable, "-m", "mimics", *COMMAND, "--out", str(out)], check=True,
                   stdout=subprocess.DEVNULL)
    return time.perf_counter() - began


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        first = one_run(Path(tmp))
        walls = [one_run(Path(tmp)) for _ in range(args.repeats)]
    median = statistics.median(walls)
    print(f"mimics {' '.join(COMMAND)}")
    print(f"  warm-up run: {first:.2f} s; cached runs: "
          f"{', '.join(f'{w:.2f}' for w in walls)} s; median {median:.2f} s (bar: < 3 s)")
    save("startup", {"command": "mimics " + " ".join(COMMAND), "warmup_s": first,
                     "cached_s": walls, "median_s": median, "bar_s": 3.0,
                     "met": median < 3.0})


if __name__ == "__main__":
    main()
