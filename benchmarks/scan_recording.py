"""What recording the laser scans costs: the Cave with and without ``record_scans``.

    python benchmarks/scan_recording.py [--times 60 600] [--repeats 3] [--warmup 1]
                                        [--algorithm deployment_team]

The Cave (100 Pioneer2DX, LMS200: 180 beams, 8 m) recorded by
``run_to_folder`` as ``mimics run`` does (per-robot logs "auto": on for 100
robots), once without and once with ``record_scans``, alternating so that
drift on a shared machine hits both alike. Whole runs are timed (start to the
last file written); figures are medians of ``--repeats`` runs after
``--warmup`` runs (before the first length only). Prints s_sim/s,
robot-steps/s, the extra wall and process CPU time (all threads; CPU time is
blurred less than wall time when other work shares the machine), the
recorder's own time (by its clock, from summary.json) and the bytes on disk
(scans.parquet alone, and the whole folder); writes
benchmarks/results/scan_recording.json.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

from common import add_run_options, folder_bytes, write_json

from mimics.records.runner import prepare, run_to_folder

RESULTS = Path(__file__).parent / "results" / "scan_recording.json"
WAYS = ("without", "with")


def timed_run(algorithm: str, sim_time: float, scans: bool, folder: Path) -> dict[str, Any]:
    """One recorded run of the Cave; its wall time, recorder time, robot-steps and bytes."""
    sim = prepare("cave", algorithm, time=sim_time, seed=1)
    start = time.perf_counter()
    cpu_start = time.process_time()
    result = run_to_folder(sim, folder, record_scans=scans)
    wall = time.perf_counter() - start
    cpu = time.process_time() - cpu_start
    summary = json.loads((folder / "summary.json").read_text())
    records = summary["records"]
    return {"wall": wall, "cpu": cpu, "recorder": records["step_time"] + records["write_time"],
            "robot_steps": records["trajectory_rows"] - sim.state.n, "steps": result.steps,
            "sim_time": result.sim_time, "folder_bytes": folder_bytes(folder),
            "scans_bytes": (folder / "scans.parquet").stat().st_size if scans else 0,
            "scan_rows": records.get("scan_rows") or 0}


def measure(algorithm: str, sim_time: float, repeats: int, warmup: int) -> dict[str, Any]:
    """Alternating runs without and with scans; medians per way."""
    runs: dict[str, list[dict[str, Any]]] = {way: [] for way in WAYS}
    with tempfile.TemporaryDirectory(prefix="mimics-scans-") as tmp:
        for attempt in range(warmup + repeats):
            for way in WAYS:
                row = timed_run(algorithm, sim_time, way == "with", Path(tmp) / way)
                if attempt >= warmup:
                    runs[way].append(row)
    out: dict[str, Any] = {}
    for way in WAYS:
        rows = runs[way]
        wall = statistics.median(r["wall"] for r in rows)
        out[way] = {"wall_time": wall, "wall_times": [r["wall"] for r in rows],
                    "cpu_time": statistics.median(r["cpu"] for r in rows),
                    "recorder_time": statistics.median(r["recorder"] for r in rows),
                    "sim_speed": rows[0]["sim_time"] / wall,
                    "robot_steps_per_s": rows[0]["robot_steps"] / wall,
                    "folder_bytes": rows[0]["folder_bytes"], "scans_bytes": rows[0]["scans_bytes"],
                    "scan_rows": rows[0]["scan_rows"], "steps": rows[0]["steps"]}
    out["extra_wall"] = out["with"]["wall_time"] - out["without"]["wall_time"]
    out["extra_cpu"] = out["with"]["cpu_time"] - out["without"]["cpu_time"]
    out["extra_recorder"] = out["with"]["recorder_time"] - out["without"]["recorder_time"]
    rows_with = out["with"]["scan_rows"]
    out["bytes_per_scan"] = out["with"]["scans_bytes"] / rows_with if rows_with else 0.0
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--times", type=float, nargs="+", default=[60.0, 600.0])
    add_run_options(parser, repeats=3)
    parser.add_argument("--warmup", type=int, default=1)
    add_run_options(parser, algorithm="deployment_team")
    args = parser.parse_args()
    load = os.getloadavg()[0]
    results: dict[str, Any] = {}
    print(f"Cave, 100 robots x 180 beams, {args.algorithm}, medians of {args.repeats} runs")
    print(f"{'sim s':>6} {'scans':>8} {'wall s':>8} {'CPU s':>7} {'s_sim/s':>8} "
          f"{'robot-steps/s':>14} {'recorder s':>11} {'folder MB':>10} {'scans MB':>9} "
          f"{'B/scan':>7}")
    for k, sim_time in enumerate(args.times):  # the first length's warm-up serves all
        figures = measure(args.algorithm, sim_time, args.repeats, args.warmup if k == 0 else 0)
        results[f"{sim_time:g}"] = figures
        for way in WAYS:
            row = figures[way]
            per_scan = f"{figures['bytes_per_scan']:7.1f}" if way == "with" else f"{'-':>7}"
            print(f"{sim_time:6g} {way:>8} {row['wall_time']:8.2f} {row['cpu_time']:7.2f} "
                  f"{row['sim_speed']:8.1f} "
                  f"{row['robot_steps_per_s']:14,.0f} {row['recorder_time']:11.3f} "
                  f"{row['folder_bytes'] / 1e6:10.2f} {row['scans_bytes'] / 1e6:9.2f} {per_scan}")
        print(f"{sim_time:6g} {'extra':>8} {figures['extra_wall']:+8.2f} s wall "
              f"({100 * figures['extra_wall'] / figures['without']['wall_time']:+.1f}%), "
              f"CPU {figures['extra_cpu']:+.2f} s "
              f"({100 * figures['extra_cpu'] / figures['without']['cpu_time']:+.1f}%), "
              f"recorder {figures['extra_recorder']:+.3f} s")
    load_after = os.getloadavg()[0]
    print(f"load average (1 min): {load:.1f} before, {load_after:.1f} after "
          f"({os.cpu_count()} cores; the machine is shared, so wall times are noisy)")
    # lengths measured at other times stay in the file, each with its own conditions
    earlier = json.loads(RESULTS.read_text()) if RESULTS.exists() else {}
    runs = earlier.get("runs", {}) if earlier.get("algorithm") == args.algorithm else {}
    for length, figures in results.items():
        runs[length] = {**figures, "repeats": args.repeats, "load_average": [load, load_after],
                        "measured": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())}
    write_json(RESULTS, {"algorithm": args.algorithm, "machine": platform.platform(),
                         "cpus": os.cpu_count(), "runs": runs})


if __name__ == "__main__":
    main()
