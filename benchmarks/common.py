"""What the benchmark scripts share: their options, timed runs, rows and results.

Benchmarks are run by hand (never by the test suite; ``benchmarks/run_all.py
--list`` names them); each prints a table and merges its figures into
``benchmarks/results.json`` (or writes ``benchmarks/results/NAME.json``).

* :func:`time_runs` times fresh simulations in this process (``logging=True``:
  recorded like ``mimics run`` into a temporary folder per run);
* :func:`run_child` and :func:`measured_row` measure one row in a fresh process
  (the script again, with ``--child SPEC``: each row's peak RSS its own,
  ``NUMBA_NUM_THREADS`` per row); the child side is :func:`measure_spec`;
* :func:`benchmark_parser` and :func:`add_run_options` give the shared options,
  :func:`save` and :func:`write_json` write the figures, :func:`with_data_folder`
  passes the Stage data folder on to processes that run another tree's code.

Only public entry points of mimics are used, never kernel internals.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import platform
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, MutableMapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # imported where a run is made: listing the benchmarks imports no engine
    from mimics.engine.simulation import Simulation

RESULTS = Path(__file__).with_name("results.json")

#: The columns every benchmark row carries (see :func:`row_from`).
ROW_COLUMNS = ["benchmark", "form", "robots", "beams_per_robot", "sim_time", "sim_speed",
               "robot_steps_per_s", "rays_per_s", "peak_rss_mb", "threads", "logging"]

#: The columns of the printed tables of :func:`measured_row`'s rows.
TABLE_COLUMNS = [*ROW_COLUMNS[1:], "us_per_robot_step"]

#: Short headers for :data:`ROW_COLUMNS` in printed tables.
HEADERS = {"beams_per_robot": "beams", "sim_speed": "s_sim/s",
           "robot_steps_per_s": "robot-steps/s", "rays_per_s": "rays/s",
           "peak_rss_mb": "peak RSS MB", "us_per_robot_step": "us/robot-step"}

Build = Callable[[dict[str, Any]], Any]


def peak_rss_mb() -> float:
    """Peak resident memory of this process so far (MB)."""
    usage = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return usage / 1024 if sys.platform != "darwin" else usage / 1024 / 1024


def numba_threads() -> int:
    """Threads numba's parallel kernels use in this process (1 without numba)."""
    try:
        import numba
    except ImportError:  # pragma: no cover - numba is a dependency of mimics
        return 1
    return int(numba.get_num_threads())


def threading_layer() -> str:
    """numba's threading layer in use ("omp", "tbb", "workqueue"; "" before any parallel run)."""
    try:
        import numba

        return str(numba.threading_layer())
    except (ImportError, ValueError):
        return ""


def state_hashes(sim: Simulation) -> dict[str, str]:
    """SHA-256 of the final pose and scan arrays (to compare runs bit for bit)."""
    state = sim.state
    return {name: hashlib.sha256(np.ascontiguousarray(getattr(state, name)).tobytes())
            .hexdigest() for name in ("pose", "scan")}


def attach_recorder(sim: Simulation, folder: str | Path, robot_logs: str = "auto") -> Any:
    """Attach the recorder ``mimics run`` uses to ``sim`` (not started yet), writing
    ``folder``: Parquet tables, per-robot logs (``"auto"``: up to 200 robots), summaries."""
    from mimics.records.recorder import RunRecorder

    recorder = RunRecorder(folder, robot_logs=robot_logs)  # type: ignore[arg-type]
    sim.observers.append(recorder)
    return recorder


def folder_bytes(folder: Path) -> int:
    """Total size of the files under ``folder``."""
    return sum(f.stat().st_size for f in folder.rglob("*") if f.is_file())


def time_runs(make: Callable[[], Simulation], repeats: int = 3, warmup: int = 1, *,
              logging: bool = False, robot_logs: str = "auto",
              warmup_make: Callable[[], Simulation] | None = None,
              min_seconds: float = 2.0, max_repeats: int = 30) -> dict[str, Any]:
    """Run fresh simulations ``warmup + repeats`` times; medians of the timed ones.

    Short runs are repeated until the timed ones add up to ``min_seconds`` of wall
    time (at most ``max_repeats``): a 70 ms run varies by 30% from one to the next.
    Returns s_sim/s, robot-steps/s and rays/s (beams cast by active robots), the
    wall and process CPU times (all threads: less blurred by a busy machine), the
    load average around the runs, numba's threading layer and hashes of the final
    pose and scan. With ``logging`` each run is recorded into a temporary folder
    (its end-of-run writing timed, its removal not). ``warmup_make`` builds the
    warm-up runs (e.g. a short one that only compiles the kernels).
    """
    walls: list[float] = []
    cpus: list[float] = []
    sample: dict[str, Any] = {}
    load = os.getloadavg()[0]
    attempt = 0
    while (attempt < warmup + repeats
           or (sum(walls) < min_seconds and attempt < warmup + max_repeats)):
        sim = (warmup_make or make)() if attempt < warmup else make()
        folder = Path(tempfile.mkdtemp(prefix="mimics-bench-")) if logging else None
        if folder is not None:
            attach_recorder(sim, folder / "run", robot_logs)
        robot_steps = 0
        rays = 0
        recorded = 0
        try:
            sim.start()
            start = time.perf_counter()
            cpu_start = time.process_time()
            beam_count = sim.types.beam_count
            while True:  # the counts in the timing: kept to two calls a step
                active = sim.state.active
                robot_steps += int(np.count_nonzero(active))
                rays += int(np.dot(beam_count, active))
                if not sim.step():
                    break
            wall = time.perf_counter() - start
            cpu = time.process_time() - cpu_start
            if folder is not None:
                recorded = folder_bytes(folder)
        finally:
            if folder is not None:
                shutil.rmtree(folder, ignore_errors=True)
        if attempt >= warmup:
            walls.append(wall)
            cpus.append(cpu)
            sample = {"sim_time": sim.state.time, "steps": sim.state.step,
                      "robot_steps": robot_steps, "rays": rays, "status": sim.status,
                      "robots": sim.state.n,
                      "beams_per_robot": float(np.mean(sim.types.beam_count)),
                      "logging": logging, "recorded_bytes": recorded,
                      "threads": numba_threads(), "threading_layer": threading_layer(),
                      "hashes": state_hashes(sim)}
        attempt += 1
    wall = statistics.median(walls)
    return {**sample, "wall_time": wall, "wall_times": walls,
            "cpu_time": statistics.median(cpus), "cpu_times": cpus,
            "load_average_before": load, "load_average_after": os.getloadavg()[0],
            "sim_speed": sample["sim_time"] / wall,
            "robot_steps_per_s": sample["robot_steps"] / wall,
            "us_per_robot_step": 1e6 * wall / max(sample["robot_steps"], 1),
            "rays_per_s": sample["rays"] / wall, "peak_rss_mb": peak_rss_mb()}


# -- one row per fresh process --------------------------------------------------

def load_algorithm(name: str, local: dict[str, Any] | None = None) -> Any:
    """An algorithm by built-in name (``find_algorithm``) or from ``local`` (the script's)."""
    if local and name in local:
        return local[name]
    from mimics.catalog import find_algorithm

    return find_algorithm(name)[1]


def default_build(spec: dict[str, Any]) -> Any:
    """The scenario of a spec: ``load_scenario(spec["scenario"], **spec["params"])``."""
    from mimics.catalog import load_scenario

    return load_scenario(spec["scenario"], **spec.get("params", {}))


def measure_spec(spec: dict[str, Any], build: Build = default_build,
                 algorithms: dict[str, Any] | None = None) -> dict[str, Any]:
    """Time the runs a spec describes, in this process. Its keys: ``algorithm``, ``time``,
    ``warmup_time`` (default ``time``), ``repeats``, ``warmup``, ``seed``, ``logging``,
    ``robot_logs``, and what ``build`` reads (default: ``scenario`` and ``params``)."""
    from mimics.engine.simulation import Simulation

    scenario = build(spec)
    algorithm = load_algorithm(spec["algorithm"], algorithms)
    name = spec["algorithm"]
    seed = int(spec.get("seed", 1))

    def make(limit: float) -> Callable[[], Simulation]:
        return lambda: Simulation(scenario, algorithm, seed=seed, time_limit=limit,
                                  algorithm_name=name)

    sim_time = float(spec["time"])
    figures = time_runs(make(sim_time), repeats=int(spec.get("repeats", 3)),
                        warmup=int(spec.get("warmup", 1)), logging=bool(spec.get("logging")),
                        robot_logs=spec.get("robot_logs", "auto"),
                        warmup_make=make(float(spec.get("warmup_time") or sim_time)))
    figures["segments"] = len(scenario.map.segments)
    for name in ("NUMBA_NUM_THREADS", "NUMBA_THREADING_LAYER", "OMP_WAIT_POLICY"):
        figures[f"env_{name}"] = os.environ.get(name, "")
    return figures


def child_main(spec_text: str, build: Build = default_build,
               algorithms: dict[str, Any] | None = None) -> None:
    """The ``--child SPEC`` side: measure the spec and print its figures as one JSON line."""
    print(json.dumps(measure_spec(json.loads(spec_text), build, algorithms)))


def run_child(script: str | Path, spec: dict[str, Any], threads: int | None = None
              ) -> dict[str, Any]:
    """Run ``script --child SPEC`` in a fresh Python process; returns its figures.

    ``threads`` sets ``NUMBA_NUM_THREADS`` for the child (default: inherited).
    """
    env = dict(os.environ)
    if threads is not None:
        env["NUMBA_NUM_THREADS"] = str(threads)
    command = [sys.executable, str(script), "--child", json.dumps(spec)]
    done = subprocess.run(command, env=env, capture_output=True, text=True)
    if done.returncode != 0:
        raise RuntimeError(f"{Path(script).name} child failed ({done.returncode}):\n"
                           f"{done.stderr[-3000:]}")
    return json.loads(done.stdout.strip().splitlines()[-1])


def row_from(benchmark: str, form: str, figures: dict[str, Any], **extra: Any
             ) -> dict[str, Any]:
    """A results row: the :data:`ROW_COLUMNS` first, then the other figures."""
    row: dict[str, Any] = {"benchmark": benchmark, "form": form}
    row.update({c: figures.get(c) for c in ROW_COLUMNS if c not in row})
    row.update(extra)
    row.update({k: v for k, v in figures.items() if k not in row})
    return row


# -- options -----------------------------------------------------------------------

#: The run options scripts share: type and help of ``--NAME`` (see :func:`add_run_options`).
RUN_OPTIONS: dict[str, tuple[type, str]] = {
    "time": (float, "simulated seconds per run"),
    "repeats": (int, "timed runs, medians reported"),
    "robots": (int, "team size, or sizes measured in turn"),
    "scenario": (str, "scenario, a built-in name"),
    "algorithm": (str, "algorithm, a built-in name"),
    "results": (Path, "results file the figures merge into")}


def add_run_options(parser: argparse.ArgumentParser, **defaults: Any) -> None:
    """Add ``--NAME`` for each ``NAME=default`` of :data:`RUN_OPTIONS`; a list default
    takes several values, None means the scenario's own (its time limit, its team)."""
    for name, default in defaults.items():
        kind, text = RUN_OPTIONS[name]
        several = isinstance(default, list)
        shown = ("the scenario's own" if default is None else " ".join(map(str, default))
                 if several else f"benchmarks/{default.name}" if kind is Path else default)
        parser.add_argument(f"--{name}", type=kind, nargs="+" if several else None,
                            default=default, help=f"{text} (default {shown})")


def benchmark_parser(doc: str | None, time: float, quick_time: float, repeats: int = 3,
                     quick_repeats: int = 1) -> argparse.ArgumentParser:
    """A parser for a script measuring rows in fresh processes: its docstring as help, the
    options such scripts share (``--quick``: ``quick_time`` and ``quick_repeats``)."""
    parser = argparse.ArgumentParser(description=doc,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--time", type=float, default=None,
                        help=f"simulated seconds per timed run (default {time:g}; "
                             f"{quick_time:g} with --quick)")
    parser.add_argument("--repeats", type=int, default=None,
                        help=f"timed runs per row, median reported (default {repeats}; "
                             f"{quick_repeats} with --quick)")
    parser.add_argument("--warmup", type=int, default=1, help="untimed warm-up runs per row")
    parser.add_argument("--warmup-time", type=float, default=1.0,
                        help="simulated seconds of each warm-up run (compiles the kernels)")
    parser.add_argument("--no-logging", dest="logging", action="store_false",
                        help="do not record the runs (default: recorded like `mimics run`)")
    parser.add_argument("--threads", type=int, default=None,
                        help="NUMBA_NUM_THREADS for the runs (default: inherited)")
    parser.add_argument("--quick", action="store_true", help="a short smoke run")
    parser.add_argument("--results", type=Path, default=RESULTS,
                        help="results file to merge into (default benchmarks/results.json)")
    parser.add_argument("--child", default=None, help=argparse.SUPPRESS)
    parser.set_defaults(default_time=time, quick_time=quick_time, default_repeats=repeats,
                        quick_repeats=quick_repeats)
    return parser


def parse_or_serve_child(parser: argparse.ArgumentParser, build: Build | None = None,
                         child: Callable[[dict[str, Any]], Any] | None = None
                         ) -> argparse.Namespace | None:
    """The parsed options; None in a ``--child`` process, once it has measured its spec
    (by ``child(spec)`` if given, else :func:`measure_spec` with ``build``) and printed
    the figures as one JSON line."""
    args = resolve(parser.parse_args())
    if args.child:
        if child is None:
            child_main(args.child, build or default_build)
        else:
            print(json.dumps(child(json.loads(args.child))))
        return None
    return args


def resolve(args: argparse.Namespace) -> argparse.Namespace:
    """Fill the defaults that depend on ``--quick``."""
    if args.time is None:
        args.time = args.quick_time if args.quick else args.default_time
    if args.repeats is None:
        args.repeats = args.quick_repeats if args.quick else args.default_repeats
    args.warmup_time = min(args.warmup_time, args.time)
    return args


def base_spec(args: argparse.Namespace, **spec: Any) -> dict[str, Any]:
    """A child spec from the shared options plus ``spec``."""
    return {"time": args.time, "repeats": args.repeats, "warmup": args.warmup,
            "warmup_time": args.warmup_time, "logging": args.logging, "seed": 1, **spec}


def meta(args: argparse.Namespace) -> dict[str, Any]:
    """What a results section records about how it was measured."""
    return {"time": args.time, "repeats": args.repeats, "warmup": args.warmup,
            "warmup_time": args.warmup_time, "logging": args.logging, "quick": args.quick,
            "threads_requested": args.threads, "cpus": os.cpu_count(),
            "machine": platform.platform(), "python": platform.python_version(),
            "measured": time.strftime("%Y-%m-%dT%H:%M:%S%z")}


# -- results and tables ------------------------------------------------------------

def save(section: str, rows: list[dict[str, Any]] | dict[str, Any],
         path: Path = RESULTS) -> None:
    """Merge ``rows`` under ``section`` into ``path`` (default benchmarks/results.json)."""
    path = Path(path)
    data = json.loads(path.read_text()) if path.exists() else {}
    data[section] = rows
    write_json(path, data)


def save_measured(args: argparse.Namespace, section: str, rows: list[dict[str, Any]],
                  **more: Any) -> None:
    """Merge a measured section (how it was measured, its rows, ``more``) into
    ``args.results``."""
    save(section, {"meta": meta(args), "rows": rows, **more}, args.results)


def write_json(path: Path, data: Any) -> None:
    """Write ``data`` as indented JSON to ``path`` (its folder made if need be)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(data, indent=2, default=str) + "\n")


def spread(values: list[float], digits: int = 2) -> str:
    """``median (lowest-highest)`` of several runs' figures."""
    return (f"{statistics.median(values):.{digits}f} "
            f"({min(values):.{digits}f}-{max(values):.{digits}f})")


def speeds_text(sim_speed: float, robot_steps_per_s: float, digits: int = 2) -> str:
    """The two speeds every benchmark prints: simulated seconds and robot-steps per wall
    second."""
    return f"{sim_speed:.{digits}f} s_sim/s, {robot_steps_per_s:,.0f} robot-steps/s"


def print_table(title: str, rows: list[dict[str, Any]], columns: list[str],
                header: bool = True) -> None:
    """A plain fixed-width table on stdout (``header=False``: the rows only)."""
    if title:
        print(title)
    if header:
        print("  ".join(f"{HEADERS.get(c, c):>14}" for c in columns))
    for row in rows:
        cells = []
        for c in columns:
            value = row.get(c, "")
            cells.append(f"{value:>14.4g}" if isinstance(value, float) else f"{value!s:>14}")
        print("  ".join(cells), flush=True)


def measured_row(script: str | Path, args: argparse.Namespace, benchmark: str, form: str,
                 columns: list[str], threads: int | None = None,
                 extra: dict[str, Any] | None = None, **spec: Any) -> dict[str, Any]:
    """One row measured by ``script --child`` in a fresh process (``spec`` on top of the
    shared options; ``threads``, default ``--threads``), printed as it comes."""
    figures = run_child(script, base_spec(args, **spec),
                        args.threads if threads is None else threads)
    row = row_from(benchmark, form, figures, **(extra or {}))
    print_table("", [row], columns, header=False)
    return row


def deployment_benchmark(script: str, name: str, label: str, targets: dict[str, float],
                         time: float, quick_time: float, doc: str,
                         rss_limit_mb: float | None = None) -> None:
    """The Cave and Hospital scripts: both forms of ``deployment`` on scenario ``name``,
    against per-form speed targets (s_sim/s) and, if given, a peak RSS limit; rows
    saved under ``name``."""
    args = parse_or_serve_child(benchmark_parser(doc, time, quick_time))
    if args is None:
        return
    print(f"{name}, {label}, {args.time:g} s simulated per run, median of "
          f"{args.repeats} after {args.warmup} warm-up of {args.warmup_time:g} s, "
          f"logging {'on' if args.logging else 'off'}")
    print_table("", [], TABLE_COLUMNS)
    rows = [measured_row(script, args, name, form, TABLE_COLUMNS, extra={"algorithm": algorithm},
                         algorithm=algorithm, scenario=name,
                         params={"fixed": True, "noise": "off"})  # the paper's set-up
            for form, algorithm in (("per-robot", "deployment"), ("team", "deployment_team"))]
    for row in rows:
        row["target_sim_speed"] = targets[row["form"]]
        row["target_met"] = row["sim_speed"] >= targets[row["form"]]
        memory = ""
        if rss_limit_mb is not None:
            row["target_rss_mb"] = rss_limit_mb
            row["target_met"] = row["target_met"] and row["peak_rss_mb"] < rss_limit_mb
            memory = f", peak RSS {row['peak_rss_mb']:.0f} MB < {rss_limit_mb:g} MB"
        print(f"  {row['form']:>9}: {speeds_text(row['sim_speed'], row['robot_steps_per_s'])}"
              f"; target >= {row['target_sim_speed']:g} s_sim/s{memory}: "
              f"{'met' if row['target_met'] else 'NOT met'}")
    save_measured(args, name, rows)


# -- the data folder ----------------------------------------------------------------

def with_data_folder(env: MutableMapping[str, str]) -> MutableMapping[str, str]:
    """``env`` with ``MIMICS_DATA`` set to the data folder as mimics finds it
    (:func:`mimics.world.data_folder.data_folder`), as an absolute path: a copy of
    ``mimics`` outside this checkout does not find ``shared/data`` by walking up."""
    from mimics.world.data_folder import ENV_VAR, data_folder

    env[ENV_VAR] = str(data_folder().resolve())
    return env
