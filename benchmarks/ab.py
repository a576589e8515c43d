"""Whole runs of a git revision and of the working tree in one process, in turn.

    python benchmarks/ab.py REV [--scenario cave] [--algorithm deployment] [--time 60]
                               [--robots N] [--seed 1] [--rounds 6] [--logging]

``alternate.py`` runs each tree in its own processes, minutes apart: on this
machine the 600 s Cave's per-robot run drifted by 15% from one such round to
the next, enough to show a gain where there was none, or a loss. Here both
codes run in this process, one run after the other (before, after, after,
before, ...), so that each pair meets the same minute of the machine. REV's
``mimics`` package is copied out of git under another name (``mimics_then``,
its own imports renamed; its kernels compile once, cached in the copy). Prints
each pair's wall times, the medians, how many pairs the working tree won, and
whether the two final states are the same bits. The first run of each is a
warm-up, not counted. ``--logging``: each run recorded, as ``mimics run`` does,
into a temporary folder (the end of run's writing counted).
"""

from __future__ import annotations

import argparse
import hashlib
import importlib
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from types import ModuleType
from typing import Any

from common import add_run_options, with_data_folder

ROOT = Path(__file__).resolve().parent.parent
COPY = "mimics_then"


def package_at(revision: str) -> ModuleType:
    """``mimics`` as it was at ``revision``, imported as the package ``mimics_then``."""
    listed = subprocess.run(["git", "-C", str(ROOT), "ls-tree", "-r", "--name-only", revision,
                             "mimics/"], capture_output=True, text=True, check=True).stdout.split()
    parts = sorted({Path(name).parts[1].removesuffix(".py") for name in listed
                    if len(Path(name).parts) > 1})
    dotted = re.compile(r"\bmimics\.(" + "|".join(map(re.escape, parts)) + r")\b")
    folder = Path(tempfile.mkdtemp(prefix="mimics-ab-"))
    for name in listed:
        target = folder / COPY / Path(name).relative_to("mimics")
        target.parent.mkdir(parents=True, exist_ok=True)
        content = subprocess.run(["git", "-C", str(ROOT), "show", f"{revision}:{name}"],
                                 capture_output=True, check=True).stdout
        if name.endswith(".py"):
            source = dotted.sub(COPY + r".\1", content.decode())
            source = source.replace("from mimics import", f"from {COPY} import")
            content = source.encode()
        target.write_bytes(content)
    sys.path.insert(0, str(folder))
    return importlib.import_module(COPY)


def run_once(package: ModuleType, args: argparse.Namespace) -> tuple[float, str]:
    """Wall time of one run with ``package``'s code, and a hash of its final poses and scans."""
    catalog = importlib.import_module(f"{package.__name__}.catalog")
    simulation = importlib.import_module(f"{package.__name__}.engine.simulation")
    params: dict[str, Any] = {} if args.robots is None else {"robots": args.robots}
    sim = simulation.Simulation(catalog.load_scenario(args.scenario, **params),
                                catalog.find_algorithm(args.algorithm)[1], seed=args.seed,
                                time_limit=args.time)
    with tempfile.TemporaryDirectory(prefix="mimics-ab-run-") as folder:
        if args.logging:
            recorder = importlib.import_module(f"{package.__name__}.records.recorder")
            sim.observers.append(recorder.RunRecorder(Path(folder) / "run"))
        start = time.perf_counter()
        sim.run()
        wall = time.perf_counter() - start
    state = sim.state
    digest = hashlib.sha256(state.pose.tobytes() + state.scan.tobytes()).hexdigest()[:16]
    return wall, digest


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("revision")
    add_run_options(parser, scenario="cave", algorithm="deployment", time=60.0, robots=None)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--rounds", type=int, default=6)
    parser.add_argument("--logging", action="store_true")
    args = parser.parse_args()
    with_data_folder(os.environ)  # REV's copy lives outside the checkout: name the data folder
    import mimics

    codes = {args.revision: package_at(args.revision), "working tree": mimics}
    digests = {name: run_once(package, args)[1] for name, package in codes.items()}  # warm-up
    walls: dict[str, list[float]] = {name: [] for name in codes}
    print(f"{args.scenario} / {args.algorithm}, {args.time:g} s, seed {args.seed}, logging "
          f"{'on' if args.logging else 'off'}: wall ms, {args.revision} then working tree")
    for round_ in range(args.rounds):
        order = list(codes) if round_ % 2 == 0 else list(reversed(codes))
        for name in order:
            wall, digests[name] = run_once(codes[name], args)
            walls[name].append(wall)
        before, after = walls[args.revision][-1], walls["working tree"][-1]
        print(f"  round {round_ + 1}: {before * 1e3:8.0f} {after * 1e3:8.0f}  "
              f"({after / before:.3f}x)")
    won = sum(a < b for a, b in zip(walls["working tree"], walls[args.revision], strict=True))
    before, after = (statistics.median(walls[name]) for name in codes)
    same = "the same bits" if len(set(digests.values())) == 1 else "NOT the same bits"
    print(f"medians {before * 1e3:.0f} and {after * 1e3:.0f} ms ({after / before:.3f}x); the "
          f"working tree faster in {won} of {args.rounds} pairs; final states: {same}")


if __name__ == "__main__":
    main()
