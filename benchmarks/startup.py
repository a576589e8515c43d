"""The fixed cost around a run: a whole ``mimics run`` process minus its loop, per scenario.

    python benchmarks/startup.py [--repeats 5] [--old PATH] [--only cave,line]

Runs each scenario's 0.1 s command (one step; logging on, as a user's run) in
fresh processes with Numba's cache and the map cache warm (an untimed run
first, which also writes Python's bytecode cache: see ``whole_process_env``),
and prints for each the median (and range) of:

* the whole process's wall time, start-up to exit;
* its CPU time (user + sys of the child): on a shared machine wall time is
  noisy, CPU time less so;
* the fixed cost: the whole process minus the loop's own wall time (the
  ``wall_time`` of the run's summary.json, which leaves compiles out).

With ``--old PATH`` (a folder holding another ``mimics`` package, e.g.
``git archive REV mimics | tar -x -C PATH``), that code's runs alternate with
this tree's (old, new, new, old, ...), so that both meet the same minutes of a
busy machine. Issue 39's bars (idle machine): Cave <= 0.5 s, Hospital <= 1.0 s,
line <= 0.4 s. Then the floor under them all: fresh processes that only import the
libraries a run imports (NumPy, Numba as mimics sets it up, Typer, Rich, pyarrow,
tomli_w) and end. Merges the figures into benchmarks/results.json under ``startup``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import RESULTS, add_run_options, save, spread, with_data_folder

COMMANDS = {"cave": ["run", "cave", "deployment", "--time", "0.1"],
            "hospital": ["run", "hospital", "deployment_team", "--time", "0.1"],
            "line": ["run", "line", "go_to_goal", "--time", "0.1"]}
BARS = {"cave": 0.5, "hospital": 1.0, "line": 0.4}


def whole_process_env(old: Path | None = None) -> dict[str, str]:
    """The environment of a timed ``mimics`` process: this one's, with Python's bytecode
    cache on (an installed package has its ``.pyc`` files; without them every module of
    mimics is compiled from source at each start: 30 to 70 ms of CPU), and ``old``'s code
    first on the path when given."""
    env = dict(os.environ)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    if old is not None:
        env["PYTHONPATH"] = str(old)
        with_data_folder(env)
    return env


def one_run(command: list[str], folder: Path, old: Path | None) -> dict[str, float]:
    """Wall, CPU and loop seconds of one ``mimics run`` in a fresh interpreter."""
    out = folder / "run"
    shutil.rmtree(out, ignore_errors=True)
    env = whole_process_env(old)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    began = time.perf_counter()
    # run in ``folder``: ``python -m`` puts the working folder first on the path, where a
    # checkout's mimics/ would shadow the one PYTHONPATH names
    subprocess.run([sys.executable, "-m", "mimics", *command, "--out", str(out)], check=True,
                   stdout=subprocess.DEVNULL, env=env, cwd=folder)
    wall = time.perf_counter() - began
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    loop = json.loads((out / "summary.json").read_text())["wall_time"]
    return {"wall": wall, "cpu": cpu, "loop": loop, "fixed": wall - loop}


# What a run imports that is not mimics' own code (NumPy, and Numba as mimics sets it up, by
# importing mimics.engine; Typer, Click and Rich for the command; pyarrow and tomli_w for the
# records): a process that imports only these and ends is the floor under every run's fixed
# cost, whatever mimics' own code does.
FLOOR = ("import mimics.engine, typer, rich.console, rich.table, pyarrow.parquet, tomli_w; "
         "import os; os._exit(0)")


def import_floor(repeats: int, old: Path | None) -> list[float]:
    """Wall seconds of fresh processes that only import what a run imports (``FLOOR``)."""
    env = whole_process_env(old)
    subprocess.run([sys.executable, "-c", FLOOR], check=True, env=env)  # bytecode written
    walls = []
    for _ in range(repeats):
        began = time.perf_counter()
        subprocess.run([sys.executable, "-c", FLOOR], check=True, env=env)
        walls.append(time.perf_counter() - began)
    return walls


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_run_options(parser, repeats=5, results=RESULTS)
    parser.add_argument("--old", type=Path, help="a folder holding another mimics package")
    parser.add_argument("--only", default=",".join(COMMANDS))
    args = parser.parse_args()
    codes: dict[str, Path | None] = {"new": None}
    if args.old is not None:
        codes = {"old": args.old.resolve(), "new": None}
    figures: dict[str, dict[str, object]] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.only.split(","):
            command = COMMANDS[name]
            for code in codes.values():
                one_run(command, Path(tmp), code)  # warm caches (Numba's, the map's)
            runs: dict[str, list[dict[str, float]]] = {label: [] for label in codes}
            for k in range(args.repeats):
                order = list(codes) if k % 2 == 0 else list(reversed(codes))
                for label in order:
                    runs[label].append(one_run(command, Path(tmp), codes[label]))
            print(f"mimics {' '.join(command)}   (bar: fixed cost <= {BARS[name]} s)")
            for label, rows in runs.items():
                columns = {key: [row[key] for row in rows] for key in ("wall", "cpu", "loop",
                                                                       "fixed")}
                print(f"  {label:>3}: whole {spread(columns['wall'])} s, cpu "
                      f"{spread(columns['cpu'])} s, loop {spread(columns['loop'])} s, "
                      f"fixed {spread(columns['fixed'])} s")
                figures[f"{name}_{label}"] = {
                    "command": "mimics " + " ".join(command),
                    **{f"{key}_median_s": statistics.median(values)
                       for key, values in columns.items()},
                    "bar_s": BARS[name]}
    floor = import_floor(args.repeats, None)
    print(f"the imports alone (no mimics code run, os._exit): whole {spread(floor)} s")
    figures["import_floor"] = {"command": f"python -c {FLOOR!r}",
                               "wall_median_s": statistics.median(floor)}
    save("startup", figures, args.results)


if __name__ == "__main__":
    main()
