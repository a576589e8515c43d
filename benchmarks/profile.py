"""Where the time goes: a pyinstrument profile of each benchmark's workload.

    python benchmarks/profile.py [--out docs/profiles] [--only cave hospital line]

Runs each workload once after a short warm-up (Numba's cache loaded), with
logging on as in the benchmarks, under pyinstrument (``pip install -e
'.[bench]'``), and writes one text profile per workload to ``--out``.
Compiled kernels show up as the frame that calls them (``_cast_rows``,
``_collide_kernel``): pyinstrument samples Python frames only.
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
from pathlib import Path

from mimics.catalog import find_algorithm, load_scenario
from mimics.engine.simulation import Simulation
from mimics.records.recorder import RunRecorder

ROOT = Path(__file__).resolve().parents[1]

# name: (scenario, parameters, algorithm, simulated seconds)
WORKLOADS = {
    "cave_per_robot": ("cave", {}, "deployment", 20.0),
    "cave_team": ("cave", {}, "deployment_team", 20.0),
    "hospital_per_robot": ("hospital", {}, "deployment", 3.0),
    "hospital_team": ("hospital", {}, "deployment_team", 3.0),
    "line_1000_per_robot": ("line", {"robots": 1000}, "go_to_goal", 5.0),
    "line_10_per_robot": ("line", {"robots": 10}, "go_to_goal", 20.0),
}


def profile(name: str, out: Path) -> Path:
    """Profile one workload; returns the text file written."""
    try:
        from pyinstrument import Profiler
    except ImportError:
        print("mimics: error: profiling needs pyinstrument: pip install -e '.[bench]'",
              file=sys.stderr)
        raise SystemExit(2) from None
    scenario_name, parameters, algorithm_name, seconds = WORKLOADS[name]
    scenario = load_scenario(scenario_name, **parameters)
    algorithm = find_algorithm(algorithm_name)[1]
    Simulation(scenario, algorithm, seed=1, time_limit=0.3).run()  # warm-up
    with tempfile.TemporaryDirectory() as folder:
        sim = Simulation(scenario, algorithm, seed=1, time_limit=seconds,
                         observers=[RunRecorder(Path(folder) / "run")])
        profiler = Profiler(interval=0.001)
        profiler.start()
        sim.run()
        profiler.stop()
    speed = sim.state.time / sim.wall_time
    text = (f"{name}: {scenario_name} {parameters or ''} / {algorithm_name}, "
            f"{sim.state.n} robots, {seconds:g} s simulated, {speed:.3g} s_sim/s under the "
            f"profiler, logging on\n\n"
            + profiler.output_text(unicode=False, color=False, show_all=False))
    path = out / f"{name}.txt"
    path.write_text(repository_relative(text))
    return path


def repository_relative(text: str) -> str:
    """A profile's text with its files named from the repository's root (``mimics/...``,
    ``benchmarks/profile.py``) or as ``<venv>/...`` and ``<python>/...``: pyinstrument
    names them from this machine's folders or from the script's (``../mimics/...``)."""
    text = text.replace(f"{ROOT}/", "").replace(f"{sys.prefix}/", "<venv>/")
    text = text.replace(f"{sys.base_prefix}/", "<python>/").replace(" ../mimics/", " mimics/")
    return re.sub(r"(?<= )profile\.py\b", "benchmarks/profile.py", text)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", type=Path, default=Path(__file__).parent.parent / "docs"
                        / "profiles")
    parser.add_argument("--only", nargs="+", choices=sorted(WORKLOADS), default=None)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for name in args.only or WORKLOADS:
        print(f"{name}: {profile(name, args.out)}", flush=True)


if __name__ == "__main__":
    main()
