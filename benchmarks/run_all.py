"""The one way into the benchmarks: list them, run one, or run the performance suite.

    python benchmarks/run_all.py --list             # every benchmark and what it measures
    python benchmarks/run_all.py NAME [ARGS ...]    # one of them, e.g. cave --quick
    python benchmarks/run_all.py [--quick] [--only cave hospital ...] [--no-logging]
                                 [--threads N] [--results benchmarks/results.json]

``--list`` reads each script's docstring (its first paragraph says what it
measures), so the list is as current as the scripts. ``NAME`` runs
``benchmarks/NAME.py`` (``peers/NAME`` for the peer comparisons) with ARGS,
its exit status passed on; ``NAME --help`` shows its options.

Without a NAME, the performance suite: ``cave.py``, ``hospital.py``,
``line_1000.py``, ``threads.py``, ``cave_tiling.py``, ``beam_scaling.py``,
``call_overhead.py``, ``cold_start.py``, ``swarm.py`` and
``battery_overhead.py``, each as its own script (each row in a fresh
process), passing ``--quick`` (short simulated times, one timed run per row:
a smoke run, not figures to quote), ``--no-logging``, ``--threads`` and
``--results`` on. Their own output is shown as they go; then one table:
benchmark, form, robots, s_sim/s, robot-steps/s, rays/s, peak RSS, and the
target with whether it is met, plus the thread speedup and determinism, the
beam fit, the per-call cost, the time to the first step with an empty and a
warm Numba cache, and the battery's per-run costs and runs/s (Figure 2
subset). All figures are merged into the results file (default
benchmarks/results.json). Nothing is asserted: the figures are for people to
read.
"""

from __future__ import annotations

import argparse
import ast
import json
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

from common import RESULTS

HERE = Path(__file__).parent
#: The scripts of this folder that are not benchmarks: the shared helpers and this entry.
NOT_BENCHMARKS = {"common", "run_all"}
#: The performance suite run without a NAME, in this order.
SUITE = ["cave", "hospital", "line_1000", "threads", "cave_tiling", "beam_scaling",
         "call_overhead", "cold_start", "swarm", "battery_overhead"]


def benchmark_scripts() -> dict[str, Path]:
    """Every benchmark script by name: ``NAME`` for ``benchmarks/NAME.py``,
    ``peers/NAME`` for ``benchmarks/peers/NAME.py``."""
    found = {path.stem: path for path in sorted(HERE.glob("*.py"))
             if path.stem not in NOT_BENCHMARKS}
    found.update({f"peers/{path.stem}": path for path in sorted((HERE / "peers").glob("*.py"))})
    return found


def description(script: Path) -> str:
    """What a benchmark measures: the first paragraph of its docstring, on one line (its
    reStructuredText quotes dropped)."""
    doc = ast.get_docstring(ast.parse(script.read_text(encoding="utf-8"))) or ""
    return " ".join(doc.split("\n\n")[0].split()).replace("``", "")


def print_list() -> None:
    """One line per benchmark: its name and what it measures."""
    scripts = benchmark_scripts()
    width = max(map(len, scripts))
    for name, script in scripts.items():
        print(f"{name:<{width}}  {description(script)}")


def run_one(name: str, arguments: list[str]) -> int:
    """Run the benchmark ``name`` with ``arguments``; its exit status (2: no such name)."""
    scripts = benchmark_scripts()
    if name not in scripts:
        print(f"run_all.py: error: NAME: no benchmark named {name!r}; expected one of "
              f"{', '.join(scripts)} (see run_all.py --list)", file=sys.stderr)
        return 2
    return subprocess.run([sys.executable, str(scripts[name]), *arguments]).returncode


def run_script(name: str, args: argparse.Namespace) -> bool:
    """Run one benchmark script with the shared options; True if it succeeded."""
    command = [sys.executable, str(HERE / f"{name}.py"), "--results", str(args.results)]
    if args.quick:
        command.append("--quick")
    if args.threads is not None and name != "threads":
        command += ["--threads", str(args.threads)]
    if not args.logging and name != "call_overhead":  # call_overhead records only if asked
        command.append("--no-logging")
    print(f"\n=== {name}: {' '.join(command[1:])}", flush=True)
    began = time.perf_counter()
    done = subprocess.run(command)
    print(f"=== {name}: {'done' if done.returncode == 0 else 'FAILED'} in "
          f"{time.perf_counter() - began:.0f} s", flush=True)
    return done.returncode == 0


def table_rows(results: dict[str, Any], names: list[str]) -> list[dict[str, Any]]:
    """The summary rows, with a target and whether it is met where the issue sets one."""
    out: list[dict[str, Any]] = []
    for name in ("cave", "hospital"):
        if name in names:
            for row in results[name]["rows"]:
                # the targets as cave.py and hospital.py judged them (their TARGETS)
                text = f">= {row['target_sim_speed']:g} s_sim/s"
                if "target_rss_mb" in row:
                    text += f", < {row['target_rss_mb'] / 1024:g} GB"
                out.append({**row, "target": text, "met": row["target_met"]})
    if "line_1000" in names:
        ratios = {r["form"]: r for r in results["line_1000"]["ratios"]}
        for row in results["line_1000"]["rows"]:
            ratio = ratios[row["form"]]
            if row["robots"] == ratio["robots_big"]:
                out.append({**row, "target": f"rs/s >= 0.5x of {ratio['robots_small']} "
                                             f"(x{ratio['ratio']:.2f})",
                            "met": ratio["target_met"]})
            else:
                out.append({**row, "target": "(reference)", "met": None})
    if "threads" in names:
        section = results["threads"]
        for row in section["rows"]:
            out.append({**row, "benchmark": f"cave {row['threads']} thr",
                        "target": f"speedup x{row['speedup']:.2f}, same state",
                        "met": row["identical_to_first"]})
    if "cave_tiling" in names:
        ratios = {r["form"]: r for r in results["cave_tiling"]["ratios"]}
        for row in results["cave_tiling"]["rows"]:
            ratio = ratios[row["form"]]
            label = f"cave {row['tiles']}"
            if row["tiles"] == ratio["big"] and ratio["big"] != ratio["small"]:
                out.append({**row, "benchmark": label,
                            "target": f"us/rs <= 1.5x of {ratio['small']} (x{ratio['ratio']:.2f})",
                            "met": ratio["target_met"]})
            else:
                out.append({**row, "benchmark": label, "target": "(reference)", "met": None})
    if "swarm" in names:
        section = results["swarm"]
        summary = section["summary"]
        for row in section["rows"]:
            if row["robots"] == summary["largest"]:
                out.append({**row, "benchmark": "swarm",
                            "target": f">= 2 s_sim/s, < 2 GB, us/rs x{summary['flatness']:.2f}"
                                      " <= 1.3",
                            "met": summary["sim_speed_met"] and summary["rss_met"]
                            and summary["flatness_met"]})
            else:
                out.append({**row, "benchmark": "swarm", "target": "(reference)", "met": None})
    if "beam_scaling" in names:
        fit = results["beam_scaling"]["fit"]
        for row in results["beam_scaling"]["rows"]:
            out.append({**row, "benchmark": f"cave {row['beams_per_robot']:g} beams",
                        "target": f"linear (R^2 {fit['r2']:.3f})", "met": None})
    return out


def print_summary(rows: list[dict[str, Any]]) -> None:
    """The one table of the issue."""
    print(f"{'benchmark':<20} {'form':<9} {'robots':>6} {'s_sim/s':>9} {'robot-steps/s':>13} "
          f"{'rays/s':>10} {'peak RSS':>9} {'log':>3}  {'target':<34} met")
    for row in rows:
        met = {True: "yes", False: "NO", None: "-"}[row["met"]]
        print(f"{row['benchmark']:<20} {row['form']:<9} {row['robots']:>6} "
              f"{row['sim_speed']:>9.3g} {row['robot_steps_per_s']:>13.4g} "
              f"{row['rays_per_s']:>10.3g} {row['peak_rss_mb']:>6.0f} MB "
              f"{'on' if row['logging'] else 'off':>3}  {row['target']:<34} {met}")


def main(argv: list[str] | None = None) -> None:
    argv = sys.argv[1:] if argv is None else argv
    if argv and not argv[0].startswith("-"):  # NAME [ARGS ...]: its options are its own
        sys.exit(run_one(argv[0], argv[1:]))
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--list", action="store_true",
                        help="name every benchmark and what it measures, and stop")
    parser.add_argument("--quick", action="store_true",
                        help="short simulated times, one timed run per row (smoke run)")
    parser.add_argument("--only", nargs="+", choices=SUITE, default=SUITE)
    parser.add_argument("--no-logging", dest="logging", action="store_false",
                        help="do not record the runs (the issue's targets are with logging)")
    parser.add_argument("--threads", type=int, default=None,
                        help="NUMBA_NUM_THREADS for all but threads.py (default: inherited)")
    parser.add_argument("--results", type=Path, default=RESULTS)
    args = parser.parse_args(argv)
    if args.list:
        print_list()
        return
    began = time.perf_counter()
    succeeded = [name for name in args.only if run_script(name, args)]
    failed = [name for name in args.only if name not in succeeded]
    results = json.loads(args.results.read_text()) if args.results.exists() else {}
    print(f"\n=== summary ({'quick smoke run, not figures to quote' if args.quick else 'full'}"
          f", {time.perf_counter() - began:.0f} s)")
    for name in ("cave", "hospital", "line_1000"):
        if name in succeeded:
            m = results[name]["meta"]
            print(f"  {name}: {m['time']:g} s simulated per run, median of {m['repeats']} "
                  f"after {m['warmup']} warm-up")
    print_summary(table_rows(results, succeeded))
    if "threads" in succeeded:
        t = results["threads"]
        print(f"threads: speedup 1 -> 2 threads x{t['speedup']:.2f}, final pose/scan "
              f"bit-identical: {'yes' if t['identical'] else 'NO'}")
    if "beam_scaling" in succeeded:
        fit = results["beam_scaling"]["fit"]
        print(f"beam scaling: us per robot-step = {fit['intercept_us']:.1f} + "
              f"{fit['us_per_beam']:.4f} * beams, R^2 = {fit['r2']:.4f}")
    if "call_overhead" in succeeded:
        for row in results["call_overhead"]["rows"]:
            print(f"per-robot call overhead ({row['algorithm']}, {row['scenario']}, "
                  f"{row['robots']} robots): {row['us_per_call']:.2f} us per call "
                  f"({row['inside_us_per_call']:.2f} us inside the call)")
    if "cold_start" in succeeded:
        section = results["cold_start"]
        for name in ("cold", "warm"):
            row = section[name]
            print(f"{name} start ({section['command']}): first step {row['first_step_s']:.2f} s, "
                  f"whole command {row['whole_s']:.2f} s, child CPU {row['cpu_s']:.2f} s; "
                  f"target <= {row['target_s']:g} s: {'met' if row['met'] else 'NOT met'}")
    if "battery_overhead" in succeeded:
        section = results["battery_overhead"]
        for row in section["rows"]:
            print(f"battery run, {row['robots']} robots (ms): build {row['build']:.1f}, steps "
                  f"{row['steps']:.1f}, recording {row['recording']:.1f}, rest of the worker "
                  f"{row['worker_other']:.1f}, parent {row['parent']:.1f}")
        total = section["summary"]
        print(f"battery ({total['runs']} runs of the Figure 2 battery): {total['seconds']:.1f} s, "
              f"{total['runs_per_s']:.2f} runs/s; 1,800 runs in about "
              f"{total['full_battery_s']:.0f} s (target <= 30 s)")
    if failed:
        print(f"FAILED: {', '.join(failed)} (see their output above)")
    print(f"figures merged into {args.results}")


if __name__ == "__main__":
    main()
