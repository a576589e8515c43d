"""The ray kernel alone, on states of the Cave and the Hospital, optionally against a revision.

    python benchmarks/ray_kernel.py [--against REV] [--repeats 40] [--no-hospital]

Runs ``deployment_team`` in the Cave to t = 0.5, 5, 20 and 45 s (and the
Hospital to 0.5 s), and times the ray kernel on each state: the minimum and
the median of ``--repeats`` calls, in µs per scanning robot, with the threads
Numba has (``NUMBA_NUM_THREADS=1`` for one). With one thread each call is
timed in process CPU time (other processes on a busy machine do not count),
with more in wall time (CPU time would add the threads up). With ``--against REV`` the ranger of git
revision REV (``mimics`` as it was there, ray kernel included) is compiled beside
this one and the two are called in turn on the same states, so that a busy
or drifting machine slows both alike; the script says whether their results
are the same bits, and if not, how far apart the ranges are and how many hit
owners differ. Like ``phases.py`` it reaches into the engine (the state,
the wall and robot indexes), so it may need changes when those do.
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time
from pathlib import Path
from types import ModuleType
from typing import Any

import numba
import numpy as np
from ab import package_at
from common import add_run_options

from mimics.catalog import find_algorithm, load_scenario
from mimics.engine.ranging import ranger
from mimics.engine.ranging.ranger import RangerQuery
from mimics.engine.simulation import Simulation

ROOT = Path(__file__).resolve().parent.parent
STATES = {"cave": (0.5, 5.0, 20.0, 45.0), "hospital": (0.5,)}


def states(names: list[str]) -> list[tuple[str, float, Simulation, RangerQuery, Any]]:
    """(scenario, time, simulation, query, robot index) at each time of ``STATES``."""
    found = []
    team = find_algorithm("deployment_team")[1]
    for name in names:
        sim = Simulation(load_scenario(name), team, seed=1, time_limit=1e6)
        sim.start()
        for when in STATES[name]:
            while sim.state.time < when - 1e-9:
                sim.step()
            state, types = sim.state, sim.types
            query = RangerQuery(np.ascontiguousarray(state.pose[:, :2]),
                                np.ascontiguousarray(state.pose[:, 2]), types.beam_offsets,
                                types.max_range, np.arange(state.n, dtype=np.int64),
                                types.beam_units, types.beam_fans)
            # a copy: later steps must not change the index this state is timed on
            index = type(sim._robot_index())(*(np.copy(a) if isinstance(a, np.ndarray) else a
                                                for a in sim._robot_index()))
            found.append((name, when, sim, query, index))
    return found


def ranger_at(revision: str) -> ModuleType:
    """``mimics/engine/ranging/ranger.py`` as it was at ``revision``, with the modules it imports
    as they were then too (the ray kernel itself is in ``ray_kernel.py``): the revision's
    ``mimics``, copied as a package of another name (``ab.package_at``)."""
    package = package_at(revision).__name__
    try:
        return importlib.import_module(f"{package}.engine.ranging.ranger")
    except ModuleNotFoundError:  # a revision from before the ranging folder
        return importlib.import_module(f"{package}.engine.ranger")


def timed(module: ModuleType, query: RangerQuery, sim: Simulation,
          index: Any) -> tuple[float, tuple[np.ndarray, np.ndarray]]:
    """Seconds for one call of ``module``'s unchecked entry point, and its results.

    ``trace_beams`` schedules its own kernel (chunk sizes differ between revisions).
    """
    clock = time.process_time if numba.get_num_threads() == 1 else time.perf_counter
    start = clock()
    out = module.trace_beams(query, sim.walls, index)
    return clock() - start, out


def agreement(now: tuple[np.ndarray, np.ndarray], then: tuple[np.ndarray, np.ndarray]) -> str:
    """Whether two kernels' ranges and owners are the same bits, and how far apart if not."""
    if now[0].tobytes() == then[0].tobytes() and np.array_equal(now[1], then[1]):
        return "same bits"
    gap = np.nanmax(np.abs(now[0] - then[0]), initial=0.0)
    owners = int(np.count_nonzero(now[1] != then[1]))
    return f"not the same bits: ranges within {gap:.1e} m, {owners} owners differ"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--against", help="a git revision whose ranger to time alongside")
    add_run_options(parser, repeats=40)
    parser.add_argument("--no-hospital", action="store_true")
    args = parser.parse_args()
    kernels = {"now": ranger}
    if args.against:
        kernels[args.against] = ranger_at(args.against)
    names = ["cave"] + ([] if args.no_hospital else ["hospital"])
    print(f"ray kernel, min (median) of {args.repeats} calls, {numba.get_num_threads()} thread(s)")
    for name, when, sim, query, index in states(names):
        k = query.offsets.shape[0]
        # the first call compiles; its results are compared
        results = {label: timed(module, query, sim, index)[1] for label, module in kernels.items()}
        times: dict[str, list[float]] = {label: [] for label in kernels}
        for _ in range(args.repeats):
            for label, module in kernels.items():  # in turn: drifts slow both alike
                times[label].append(timed(module, query, sim, index)[0])
        best = {label: min(seconds) for label, seconds in times.items()}
        row = "  ".join(f"{label} {best[label] / k * 1e6:6.2f} us/robot "
                        f"(median {np.median(seconds) / k * 1e6:6.2f})"
                        for label, seconds in times.items())
        if args.against:
            speedup = best[args.against] / best["now"]
            row += f"  ({speedup:.2f}x, {agreement(results['now'], results[args.against])})"
        print(f"{name:9s} t = {when:4g} s, {k} robots: {row}")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
