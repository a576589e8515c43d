"""A class of 60 graded end to end with the teacher's kit: wall time, per-run cost, marks.

    python benchmarks/class_of_60.py [--students 60] [--workers 2] [--isolation run]
                                     [--timeout 20] [--keep DIR]

Copies ``examples/teaching_kit`` to a scratch folder, writes ``--students``
generated submissions into its ``submissions/`` (each a distinct file: good
solutions, the gallery's reciprocal avoidance each with its own safety margin,
six-line "turn right when blocked" rules with their own gains, and the
broken kinds a class hands in: an exception on one scenario, a NaN, a step that
hangs, a syntax error, an endless loop at import, and two byte-for-byte copies),
then grades them as the kit's README says: ``battery run teacher/grading.toml``
(the starter's reference row), ``battery add`` of every submission, ``battery
report --grade``. The battery's run time-out is set to ``--timeout`` seconds (the
kit's is 120: the hanging submissions would then cost minutes of waiting each).
Prints the wall time of each command, the runs and seconds per run, the mark of
each kind of submission (min-max), and whether the copies were flagged.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd

KIT = Path(__file__).resolve().parents[1] / "examples" / "teaching_kit"

# a good solution: the gallery's reciprocal avoidance, each student with their own margin
GOOD = (KIT.parent / "reciprocal_avoidance" / "algorithm.py").read_text()
TURN_RIGHT = ("import numpy as np\n\n\n"
              "def step(robot):\n"
              "    x, y, _ = robot.pose\n"
              "    heading = np.arctan2(robot.goal[1] - y, robot.goal[0] - x)\n"
              "    blocked = (np.abs(robot.scan.angles) < 0.6) & (robot.scan.ranges < {reach})\n"
              "    return (0.2, heading - {turn}) if blocked.any() else (0.5, heading)\n")
BROKEN = {
    "raises": ("def step(robot):\n"
               "    if len(robot.comms) == 8:  # the crossroads only\n"
               "        raise ValueError('no way through')\n"
               "    return 0.0, robot.heading\n"),
    "nan": "def step(robot):\n    return float('nan'), robot.heading\n",
    "hangs": ("def step(robot):\n    while True:\n        pass\n"),
    "syntax": "def step(robot)\n    return 0.0, robot.heading\n",
    "loops_at_import": "while True:\n    pass\n\n\ndef step(robot):\n    return 0.0, 0.0\n",
}


def submissions(count: int) -> dict[str, str]:
    """``count`` files (name -> text): 60% good, 25% turn-right rules, the rest broken,
    two of them copies of a good one."""
    files: dict[str, str] = {}
    broken = list(BROKEN.items())
    n_broken = max(len(broken), count // 8)
    n_rules = count // 4
    n_good = count - n_broken - n_rules - 2
    for k in range(n_good):
        files[f"good_{k:02d}"] = GOOD.replace("MARGIN = 0.15", f"MARGIN = {0.15 + 0.002 * k:.3f}")
    for k in range(n_rules):
        files[f"rule_{k:02d}"] = TURN_RIGHT.format(reach=round(0.8 + 0.05 * k, 2),
                                                    turn=round(0.8 + 0.04 * k, 2))
    for k in range(n_broken):
        kind, text = broken[k % len(broken)]
        files[f"{kind}_{k:02d}"] = text + f"# student {k}\n"
    files["copy_a"] = files["copy_b"] = files["good_00"]
    return files


def mimics(*args: str, cwd: Path) -> tuple[float, subprocess.CompletedProcess[str]]:
    start = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "mimics", *args], cwd=cwd, text=True,
                          capture_output=True, check=False)
    return time.perf_counter() - start, done


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--students", type=int, default=60)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--isolation", choices=("run", "worker"), default="run")
    parser.add_argument("--timeout", type=float, default=20.0)
    parser.add_argument("--keep", type=Path, help="Grade in this folder and keep it.")
    args = parser.parse_args()
    root = args.keep or Path(tempfile.mkdtemp(prefix="class60-"))
    kit = root / "kit"
    shutil.copytree(KIT, kit, ignore=shutil.ignore_patterns("__pycache__"))
    for name, text in submissions(args.students).items():
        (kit / "submissions" / f"{name}.py").write_text(text)
    grading = kit / "teacher" / "grading.toml"
    text = grading.read_text()
    text = text.replace("timeout = 120", f"timeout = {args.timeout:g}")
    text = text.replace('isolation = "run"', f'isolation = "{args.isolation}"')
    grading.write_text(text)
    steps = {}
    steps["run (starter)"], _ = mimics("battery", "run", "teacher/grading.toml", "--out",
                                          "class-1", "--workers", str(args.workers),
                                          cwd=kit)
    files = sorted(str(p.relative_to(kit)) for p in (kit / "submissions").glob("*.py"))
    steps["add (the class)"], added = mimics("battery", "add", "class-1", *files,
                                             "--workers", str(args.workers), cwd=kit)
    steps["report --grade"], report = mimics("battery", "report", "class-1", "--grade",
                                             "grade.py", cwd=kit)
    if report.returncode != 0:
        print(report.stdout[-2000:], report.stderr[-2000:])
        return 1
    marks = pd.read_csv(kit / "class-1" / "marks.csv")
    runs = int(marks["runs"].sum())
    total = sum(steps.values())
    print(f"{len(files)} submissions, {runs} runs, {args.workers} workers, isolation "
          f"{args.isolation}, run time-out {args.timeout:g} s")
    for step, seconds in steps.items():
        print(f"  {step:18s} {seconds:7.1f} s")
    print(f"  {'total':18s} {total:7.1f} s ({total / max(runs, 1):.2f} s per run)")
    kinds = marks.assign(kind=marks["student"].str.replace(r"_\w+$", "", regex=True))
    print("marks by kind (min-max):")
    for kind, rows in kinds.groupby("kind"):
        print(f"  {kind:16s} {rows['mark'].min():4.1f} - {rows['mark'].max():4.1f}"
              f"  ({len(rows)})")
    flagged = marks.loc[marks["student"].isin(["copy_a", "copy_b"]), "copy_of"].tolist()
    print(f"copies flagged: {flagged}")
    print(f"folder: {kit}" if args.keep else "")
    if not args.keep:
        shutil.rmtree(root)
    return 0 if added.returncode in (0, 1) else 1


if __name__ == "__main__":
    sys.exit(main())
