"""Time from a fresh ``mimics run`` to its first simulated step, with Numba's cache empty or warm.

    python benchmarks/cold_start.py [--repeats 3] [--quick] [--laser] [--no-table]
                                    [--results benchmarks/results.json]
    python benchmarks/cold_start.py --parts [--repeats 3]

``--parts`` compiles each part of the first-run compile (``mimics.engine.compiling.warm_up``:
index, motion, the ray kernel, its helpers, still) alone in a fresh process with
an empty cache and prints its CPU seconds (median) and its kernels' own compile
times (nested compiles subtracted), slowest first: where a cold run's CPU goes,
whatever the machine's load (the cold run's table below gives wall seconds, which
depend on how the parts share the cores). Not saved.

``--laser`` times issue 39's command instead, ``mimics run cave deployment
--time 1``: the first run that reads the laser, whose bar is the whole
command with an empty cache <= 10 s on two cores (the compile is reported on
the summary's own ``compile`` line and left out of the run's wall time).

Runs the README's command, ``mimics run line go_to_goal --robots 60 --seed 1``,
in fresh interpreters, each one as a user would (``python -m mimics``):

* cold: every run gets a fresh, empty ``NUMBA_CACHE_DIR``, as on a machine just
  after ``pip install`` (the CLI's first-run compile included);
* warm: runs sharing one cache folder, filled by an untimed run first.

For each it prints the median (and range) of the wall time to the end of the
run's first step and of the whole command, and the CPU time (user + sys) of
the child, ``getrusage(RUSAGE_CHILDREN)``: on a shared machine wall time is
noisy, CPU time less so. The first step is timed by a small wrapper around
``Simulation.step`` inside the child (the last simulation a run starts is the
user's; the CLI's first-run compile runs a tiny one before it). One more cold
run records every Numba compile (``numba.core.event``) in every process of the
run, the run's own and the compile processes it starts (``index`` and the ray
kernel's helpers are compiled by the run's process, ``motion``, the ray kernel
and ``still`` each by a process of its own, a fork of the run; a
``sitecustomize`` put on the children's ``PYTHONPATH`` registers the listener,
so this run is untimed), and prints the per-kernel table:
seconds per kernel and signature, with the process that compiled it, nested
compiles included in their caller's time. A kernel listed by two processes
was compiled twice. Targets (issue 21): cold <= 10 s, warm <= 1.5 s.
Merges the figures into benchmarks/results.json under ``cold_start``.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from common import RESULTS, add_run_options, save

COMMAND = ["run", "line", "go_to_goal", "--robots", "60", "--seed", "1"]
# issue 39: the first run that reads the laser, timed as a whole process (<= 10 s)
LASER_COMMAND = ["run", "cave", "deployment", "--time", "1"]
COLD_TARGET_S, WARM_TARGET_S = 10.0, 1.5

# Runs inside the child: the CLI as `python -m mimics` would, plus a clock on the first
# step of each simulation.
CHILD = r"""
import atexit, json, sys, time
out = sys.argv[1]
sys.argv = ["mimics", *sys.argv[2:]]
firsts = []
from mimics.engine.simulation import Simulation

step = Simulation.step

def timed_step(self):
    more = step(self)
    if not getattr(self, "_bench_stepped", False):
        self._bench_stepped = True
        firsts.append(time.monotonic())
    return more

Simulation.step = timed_step

@atexit.register
def _dump():
    with open(out, "w") as f:
        json.dump({"first_steps": firsts}, f)

from mimics.interfaces.cli.leave import console  # what `mimics` and `python -m mimics` run
console()
"""

# The sitecustomize of the run that lists the compiles: every Python process of the run
# (the run's own, the compile processes) appends each compile to a file of its own as it
# ends (a compile process ends by os._exit, without exit handlers). The process is named
# by the part it compiles, or "run".
EVENTS_SITE = r"""
import json, os, re, time
folder = os.environ["MIMICS_BENCH_COMPILES"]
from numba.core import event


def process_name():
    # a compile process forked by the run is named mimics-PART (ps's comm); a spawned one
    # calls compile_part('PART') on its command line
    with open("/proc/self/comm") as f:
        comm = f.read().strip()
    if comm.startswith("mimics-"):
        return comm.removeprefix("mimics-")
    with open("/proc/self/cmdline", "rb") as f:
        found = re.search(rb"compile_part\('(\w+)'", f.read())
    return found.group(1).decode() if found else "run"

class _Timer(event.Listener):
    def __init__(self):
        self.open = []

    def on_start(self, ev):
        self.open.append(time.monotonic())

    def on_end(self, ev):
        began = self.open.pop()
        d = ev.data["dispatcher"]
        row = {"kernel": d.py_func.__module__ + "." + d.py_func.__qualname__,
               "args": str(ev.data["args"]), "depth": len(self.open),
               "s": time.monotonic() - began, "process": process_name()}
        with open(os.path.join(folder, f"{os.getpid()}.jsonl"), "a") as f:
            f.write(json.dumps(row) + "\n")

event.register("numba:compile", _Timer())
"""


def one_run(cache: Path, folder: Path, command: list[str], events: bool = False
            ) -> dict[str, Any]:
    """Wall and CPU seconds of one ``mimics run`` in a fresh interpreter using ``cache``;
    with ``events``, also every Numba compile of its processes (``compiles``)."""
    dump = folder / "child.json"
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache)}
    compiles = folder / "compiles"
    if events:
        (folder / "site").mkdir(exist_ok=True)
        (folder / "site" / "sitecustomize.py").write_text(EVENTS_SITE)
        compiles.mkdir(exist_ok=True)
        env["PYTHONPATH"] = os.pathsep.join(
            p for p in (str(folder / "site"), env.get("PYTHONPATH")) if p)
        env["MIMICS_BENCH_COMPILES"] = str(compiles)
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    began = time.monotonic()
    subprocess.run([sys.executable, "-c", CHILD, str(dump), *command,
                    "--out", str(folder / "run")], check=True, env=env,
                   stdout=subprocess.DEVNULL)
    wall = time.monotonic() - began
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    child = json.loads(dump.read_text())
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    rows = [json.loads(line) for path in sorted(compiles.glob("*.jsonl"))
            for line in path.read_text().splitlines()] if events else []
    return {"first_step_s": child["first_steps"][-1] - began, "whole_s": wall, "cpu_s": cpu,
            "compiles": rows}


def summary(runs: list[dict[str, Any]]) -> dict[str, Any]:
    """Medians and ranges of the runs' figures."""
    out: dict[str, Any] = {"runs": len(runs)}
    for key in ("first_step_s", "whole_s", "cpu_s"):
        values = [r[key] for r in runs]
        out[key] = statistics.median(values)
        out[key + "_range"] = [min(values), max(values)]
    return out


def kernel_table(compiles: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """One row per kernel and signature, slowest first."""
    rows = [{"kernel": c["kernel"].removeprefix("mimics.engine."), "depth": c["depth"],
             "s": round(c["s"], 3), "args": c["args"], "process": c["process"]}
            for c in compiles]
    return sorted(rows, key=lambda r: -r["s"])


# Runs inside a child of --parts: one warm-up part, timed on the CPU, with each kernel's
# compile time less that of the compiles nested in it.
PART_CHILD = r"""
import json, sys, time
began = time.process_time()
from numba.core import event
stack, rows = [], []

class Timer(event.Listener):
    def on_start(self, ev):
        stack.append([time.process_time(), 0.0])

    def on_end(self, ev):
        began, nested = stack.pop()
        took = time.process_time() - began
        if stack:
            stack[-1][1] += took
        d = ev.data["dispatcher"]
        rows.append([d.py_func.__module__ + "." + d.py_func.__qualname__, took - nested])

event.register("numba:compile", Timer())
from mimics.engine.compiling import warm_up
imported = time.process_time()
getattr(warm_up, sys.argv[2])()
done = time.process_time()
with open(sys.argv[1], "w") as f:
    json.dump({"import_s": imported - began, "compile_s": done - imported, "kernels": rows}, f)
"""
PART_STEPS = ("compile_index_kernels", "compile_motion_kernels", "compile_ray_kernel",
              "compile_ray_helpers", "compile_still_kernels")


def time_parts(repeats: int) -> None:
    """Each warm-up part alone in fresh processes, empty caches: median CPU seconds."""
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        for step in PART_STEPS:
            runs = []
            for k in range(repeats):
                out = root / f"{step}-{k}.json"
                env = {**os.environ, "NUMBA_CACHE_DIR": str(root / f"cache-{step}-{k}")}
                subprocess.run([sys.executable, "-c", PART_CHILD, str(out), step], check=True,
                               env=env)
                runs.append(json.loads(out.read_text()))
            compile_s = statistics.median(r["compile_s"] for r in runs)
            import_s = statistics.median(r["import_s"] for r in runs)
            kernels = runs[0]["kernels"]
            print(f"{step}: {compile_s:.2f} s CPU compiling (median of {repeats}; import "
                  f"{import_s:.2f} s), {len(kernels)} compiles")
            for name, own in sorted(kernels, key=lambda r: -r[1])[:6]:
                print(f"  {own:6.2f}  {name.removeprefix('mimics.engine.')}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--quick", action="store_true",
                        help="one run of each, 0.1 s simulated (a smoke run)")
    parser.add_argument("--warm-only", action="store_true",
                        help="only the warm runs (no cold runs, no compile table; not saved)")
    parser.add_argument("--threads", type=int, default=None, help="NUMBA_NUM_THREADS")
    parser.add_argument("--no-logging", action="store_true", help="ignored (runs always log)")
    parser.add_argument("--laser", action="store_true",
                        help="time issue 39's command instead: mimics run cave deployment "
                             "--time 1 (the first run that reads the laser); its bar is the "
                             "whole command, cold, <= 10 s")
    parser.add_argument("--no-table", action="store_true",
                        help="skip the extra cold run that lists every compile")
    parser.add_argument("--parts", action="store_true",
                        help="CPU seconds of each part of the first-run compile, alone in a "
                             "fresh process (not saved)")
    add_run_options(parser, results=RESULTS)
    args = parser.parse_args()
    if args.parts:
        time_parts(args.repeats)
        return
    if args.threads is not None:
        os.environ["NUMBA_NUM_THREADS"] = str(args.threads)
    command = (LASER_COMMAND if args.laser else COMMAND) + (["--time", "0.1"] if args.quick
                                                            else [])
    repeats = 1 if args.quick else args.repeats
    cold: list[dict[str, Any]] = []
    warm: list[dict[str, Any]] = []
    with tempfile.TemporaryDirectory() as tmp:
        root = Path(tmp)
        shared = root / "warm-cache"
        one_run(shared, root, command)  # fills the shared cache, untimed
        for k in range(repeats):  # alternated, so that load changes hit both alike
            if not args.warm_only:
                cold.append(one_run(root / f"cold-cache-{k}", root, command))
            warm.append(one_run(shared, root, command))
        if args.warm_only:
            warm_s = summary(warm)
            lo, hi = warm_s["first_step_s_range"]
            print(f"warm: first step {warm_s['first_step_s']:.2f} s ({lo:.2f}-{hi:.2f}), whole "
                  f"command {warm_s['whole_s']:.2f} s, child CPU {warm_s['cpu_s']:.2f} s "
                  f"(median of {repeats}); target first step <= {WARM_TARGET_S:g} s")
            return
        table = [] if args.no_table else kernel_table(
            one_run(root / "cold-cache-events", root, command, events=True)["compiles"])
    cold_s, warm_s = summary(cold), summary(warm)
    print(f"mimics {' '.join(command)}  (medians of {repeats}, fresh processes)")
    for name, s, target in (("cold", cold_s, COLD_TARGET_S), ("warm", warm_s, WARM_TARGET_S)):
        lo, hi = s["first_step_s_range"]
        print(f"  {name}: first step {s['first_step_s']:.2f} s ({lo:.2f}-{hi:.2f}), whole "
              f"command {s['whole_s']:.2f} s, child CPU {s['cpu_s']:.2f} s; target first "
              f"step <= {target:g} s: {'met' if s['first_step_s'] <= target else 'NOT met'}")
    if table:
        top = [r for r in table if r["depth"] == 0]
        processes = sorted({r["process"] for r in table})
        print(f"Numba compiles of one cold run: {len(table)} (kernel, signature) pairs in "
              f"{len(processes)} processes ({', '.join(processes)}), "
              f"{sum(r['s'] for r in top):.2f} s in top-level calls (wall, each process's own)")
        print(f"  {'s':>6} depth  {'process':<7}  kernel")
        for row in table:
            print(f"  {row['s']:>6.2f} {row['depth']:>5}  {row['process']:<7}  {row['kernel']}")
    key = "cold_start_laser" if args.laser else "cold_start"
    save(key, {"command": "mimics " + " ".join(command), "repeats": repeats,
                        "cold": {**cold_s, "target_s": COLD_TARGET_S,
                                 "met": cold_s["first_step_s"] <= COLD_TARGET_S},
                        "warm": {**warm_s, "target_s": WARM_TARGET_S,
                                 "met": warm_s["first_step_s"] <= WARM_TARGET_S},
                        "compiles": table}, args.results)


if __name__ == "__main__":
    main()
