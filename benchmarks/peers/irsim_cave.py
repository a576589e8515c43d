"""The Cave workload in IR-SIM and in mimics, side by side.

    pip install -e '.[peers]'        # IR-SIM (ir-sim==2.12.0), an optional extra
    python benchmarks/peers/irsim_cave.py [--time 2] [--mimics-time 60] [--repeats 3]
        [--map filled|irsim] [--no-logging] [--threads N]

Both sides: 100 differential-drive robots with a 180-beam, 180 deg, 8 m lidar
on the 16 x 16 m Cave of Stage, starting at cave.world's start poses, dt 0.1 s,
driven by the "expand"/deployment rule (turn toward the sum of the range
vectors, drive at 0.2 m/s when facing it with room ahead). mimics runs its
built-in ``cave`` scenario with ``deployment`` (per robot) and
``deployment_team`` (whole team), each in a fresh process (one short warm-up
compiles the kernels, then the median of ``--repeats`` runs of
``--mimics-time`` s). IR-SIM runs headless (no figure) in this process; its
world YAML is written to a temporary folder; the median of ``--repeats``
fresh runs of ``--time`` s (building the world is not timed). The differences
between the two workloads are listed in benchmarks/peers/README.md.

Prints one row per simulator/form and the ratios mimics / IR-SIM, and merges
the figures into benchmarks/results.json under ``peers_irsim``. The machine
is shared: wall times are noisy, CPU times are recorded beside them.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib.util
import io
import os
import platform
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # benchmarks/: common.py

from common import RESULTS, child_main, peak_rss_mb, print_table, run_child, save

IRSIM_VERSION = "2.12.0"  # the version the extra pins (pyproject.toml, `peers`)
FORMS = {"per-robot": "deployment", "team": "deployment_team"}
COLUMNS = ["simulator", "form", "robots", "mean_active", "beams_per_robot", "sim_time",
           "sim_speed", "robot_steps_per_s", "rays_per_s", "cpu_sim_speed", "peak_rss_mb"]
HEADERS = {"mean_active": "active (mean)", "beams_per_robot": "beams", "sim_time": "sim s",
           "sim_speed": "s_sim/s", "robot_steps_per_s": "robot-steps/s", "rays_per_s": "rays/s",
           "cpu_sim_speed": "s_sim/CPU-s", "peak_rss_mb": "peak RSS MB"}

# The deployment rule's constants, as mimics.algorithms.deployment sets them for a
# Pioneer2DX (length 0.325 m, top speed 0.3 m/s, 8 m laser).
SPEED = 2 / 3  # cruise, fraction of top speed
MAX_TURN = 0.5  # rad
REACH, AHEAD, STOPPING, AHEAD_RANGE = 1.0, 2.0, 3.0, 0.25
TURN_GAIN = 1.0  # rad/s per rad of heading error (Stage's expand controller)
CORNERS = [[-8.0, -8.0], [8.0, -8.0], [8.0, 8.0], [-8.0, 8.0]]  # the Cave's bounds (m)


def require_irsim() -> Any:
    """Import IR-SIM headless, or exit with status 2 and a one-line hint."""
    if importlib.util.find_spec("irsim") is None:
        print("irsim_cave.py: IR-SIM is not installed; install it with "
              "pip install -e '.[peers]'", file=sys.stderr)
        sys.exit(2)
    os.environ.setdefault("MPLBACKEND", "Agg")
    import matplotlib

    matplotlib.use("Agg")
    # irsim tries TkAgg/Qt5Agg on import and prints each failure; keep stdout clean
    with contextlib.redirect_stdout(io.StringIO()):
        import irsim
    matplotlib.use("Agg")
    if irsim.__version__ != IRSIM_VERSION:
        print(f"note: IR-SIM {irsim.__version__} installed, the extra pins {IRSIM_VERSION}")
    return irsim


def cave_setup(map_choice: str, irsim: Any) -> dict[str, Any]:
    """Start poses, robot type and bitmap of the Cave (poses/type from mimics' scenario)."""
    from mimics.catalog import load_scenario
    from mimics.world.data_folder import find_stage_file

    scenario = load_scenario("cave")
    kind = scenario.types[0]
    # the map is recorded by where it comes from: its path would name this machine's folders
    if map_choice == "filled":  # the bitmap mimics' cave vectorises (Stage's cave.world)
        bitmap, label = find_stage_file("cave_filled.png"), "data folder: stage/cave_filled.png"
    else:  # IR-SIM's packaged cave.png (Stage's cave.png: walls drawn as outlines)
        bitmap = Path(irsim.__file__).parent / "world" / "map" / "cave.png"
        label = "ir-sim package: world/map/cave.png"
    return {"poses": np.asarray(scenario.as_matrix())[:, :3].astype(float), "type": kind,
            "bitmap": str(bitmap), "map_label": label,
            "scenario_time_limit": scenario.settings.time_limit}


def world_yaml(setup: dict[str, Any], folder: Path) -> Path:
    """Write IR-SIM's world file for the Cave; returns its path."""
    import yaml

    kind = setup["type"]
    world = {
        "world": {"width": 16, "height": 16, "offset": [-8, -8],
                  "step_time": 0.1, "sample_time": 0.1, "collision_mode": "stop",
                  "obstacle_map": setup["bitmap"]},
        "robot": [{
            "number": len(setup["poses"]),
            "distribution": {"name": "manual"},
            "kinematics": {"name": "diff"},
            # the Pioneer2DX body mimics uses (length along the heading)
            "shape": {"name": "rectangle", "length": float(kind.length),
                      "width": float(kind.width)},
            "state": [[float(v) for v in pose] for pose in setup["poses"]],
            "goal": [[0.0, 100.0, 0.0]] * len(setup["poses"]),  # outside the map: never reached
            "vel_max": [float(kind.kv), float(kind.kw)],
            "vel_min": [-float(kind.kv), -float(kind.kw)],
            "sensors": [{"name": "lidar2d", "range_min": 0.0,
                         "range_max": float(kind.ranger.range),
                         "angle_range": float(kind.ranger.fov),
                         "number": int(kind.ranger.beams), "noise": False}],
        }],
        # Stage's floorplan `boundary 1` (mimics keeps it): walls along the map's edges,
        # where the bitmap's free space reaches the edge in the west. Four straight
        # lines, not one closed square: IR-SIM checks every object against the map grid
        # over its bounding box, which for a square is the whole 500 x 500 grid.
        "obstacle": [{"number": 1, "distribution": {"name": "manual"},
                      "state": [[0.0, 0.0, 0.0]], "static": True,
                      "shape": {"name": "linestring", "vertices": [start, end]}}
                     for start, end in zip(CORNERS, CORNERS[1:] + CORNERS[:1], strict=True)],
    }
    path = folder / "cave_irsim.yaml"
    path.write_text(yaml.safe_dump(world, sort_keys=False))
    return path


class Deployment:
    """The deployment rule for all IR-SIM robots at once (numpy, from their lidar ranges)."""

    def __init__(self, angles: np.ndarray, kind: Any) -> None:
        self.sin, self.cos = np.sin(angles), np.cos(angles)
        self.cruise = SPEED * float(kind.kv)
        ahead = min(max(AHEAD * kind.length, STOPPING * self.cruise),
                    AHEAD_RANGE * kind.ranger.range)
        self.needed = REACH * kind.length + ahead * np.maximum(self.cos, 0.0)
        self.max_turn_rate = float(kind.kw)

    def __call__(self, ranges: np.ndarray) -> list[np.ndarray]:
        """One ``[[v], [w]]`` command per robot from ``ranges`` ``(n, beams)``."""
        turn = np.arctan2(ranges @ self.sin, ranges @ self.cos)
        clear = np.all(ranges > self.needed, axis=1)
        speed = np.where((np.abs(turn) < MAX_TURN) & clear, self.cruise, 0.0)
        rate = np.clip(TURN_GAIN * turn, -self.max_turn_rate, self.max_turn_rate)
        return [np.array([[v], [w]]) for v, w in zip(speed, rate, strict=True)]


def irsim_run(irsim: Any, world: Path, setup: dict[str, Any], sim_time: float
              ) -> dict[str, Any]:
    """Build a fresh IR-SIM world and time ``sim_time`` simulated seconds of it."""
    built = time.perf_counter()
    env = irsim.make(str(world), headless=True, log_level="ERROR", seed=1)
    build_time = time.perf_counter() - built
    robots = env.robot_list
    beams = int(robots[0].lidar.number)
    control = Deployment(robots[0].lidar.angle_list, setup["type"])
    first_scan = np.stack([robot.lidar.range_data for robot in robots])  # taken by make()
    steps = round(sim_time / env.step_time)
    start, cpu_start = time.perf_counter(), time.process_time()
    for _ in range(steps):
        ranges = np.stack([robot.lidar.range_data for robot in robots])
        env.step(control(ranges), action_id=robots[0].id)  # actions to robots 0..n-1
    wall = time.perf_counter() - start
    cpu = time.process_time() - cpu_start
    stopped = sum(bool(robot.stop_flag) for robot in robots)
    moved = float(np.mean([np.hypot(*(robot.state[:2, 0] - pose[:2]))
                           for robot, pose in zip(robots, setup["poses"], strict=True)]))
    from irsim.lib.algorithm.ray_casting_2d import boundary_segments

    map_segments = sum(len(boundary_segments(obj.linestrings)[0])
                       for obj in env.objects if obj.shape == "map")
    env.end(ending_time=0)
    return {"wall_time": wall, "cpu_time": cpu, "build_time": build_time, "steps": steps,
            "sim_time": steps * env.step_time, "robots": len(robots),
            "beams_per_robot": float(beams), "robot_steps": steps * len(robots),
            "rays": steps * len(robots) * beams, "stopped_by_collision": stopped,
            "mean_distance_moved": moved, "map_segments": map_segments,
            "first_scan": first_scan}


def measure_irsim(irsim: Any, setup: dict[str, Any], sim_time: float, repeats: int
                  ) -> dict[str, Any]:
    """Median of ``repeats`` fresh IR-SIM runs (all robots scan every step)."""
    runs = []
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="mimics-peers-") as folder:
        world = world_yaml(setup, Path(folder))
        for _ in range(repeats):
            runs.append(irsim_run(irsim, world, setup, sim_time))
            print(f"  IR-SIM run: {runs[-1]['wall_time']:.1f} s wall for "
                  f"{runs[-1]['sim_time']:g} s simulated", flush=True)
    agreement = scan_agreement(runs[0].pop("first_scan"))
    for run in runs:
        run.pop("first_scan", None)
    walls = [r["wall_time"] for r in runs]
    wall, cpu = statistics.median(walls), statistics.median(r["cpu_time"] for r in runs)
    last = runs[-1]
    return {**last, "simulator": f"IR-SIM {irsim.__version__}", "form": "numpy rule",
            "wall_time": wall, "wall_times": walls, "cpu_time": cpu,
            "cpu_times": [r["cpu_time"] for r in runs],
            "build_times": [r["build_time"] for r in runs],
            "sim_speed": last["sim_time"] / wall, "cpu_sim_speed": last["sim_time"] / cpu,
            "robot_steps_per_s": last["robot_steps"] / wall,
            "rays_per_s": last["rays"] / wall, "peak_rss_mb": peak_rss_mb(),
            "load_average_before": load, "load_average_after": os.getloadavg()[0],
            "map": setup["map_label"], **agreement}


def scan_agreement(irsim_scan: np.ndarray) -> dict[str, float]:
    """How closely IR-SIM's first scans match mimics' at the same start poses.

    Both scan right to left over 180 deg; a check that the two maps and lidars
    see the same Cave (they differ by the bitmap's pixel steps only).
    """
    from mimics.catalog import find_algorithm, load_scenario
    from mimics.engine.simulation import Simulation

    sim = Simulation(load_scenario("cave"), find_algorithm("deployment")[1], seed=1,
                     time_limit=0.1)
    sim.start()
    diff = np.abs(irsim_scan - np.asarray(sim.state.scan))
    return {"scan_median_abs_diff_m": float(np.median(diff)),
            "scan_p90_abs_diff_m": float(np.percentile(diff, 90)),
            "scan_fraction_within_0_1m": float(np.mean(diff <= 0.1))}


def measure_mimics(args: argparse.Namespace) -> list[dict[str, Any]]:
    """One row per form, each in a fresh process (``common.run_child``)."""
    rows = []
    for form, algorithm in FORMS.items():
        spec = {"scenario": "cave", "algorithm": algorithm, "time": args.mimics_time,
                "repeats": args.repeats, "warmup": 1,
                "warmup_time": min(1.0, args.mimics_time), "logging": args.logging,
                "seed": 1}
        figures = run_child(__file__, spec, args.threads)
        figures["cpu_sim_speed"] = figures["sim_time"] / figures["cpu_time"]
        rows.append({"simulator": "mimics", "form": form, "algorithm": algorithm,
                     **figures})
        print(f"  mimics {form}: {figures['sim_speed']:.2f} s_sim/s", flush=True)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--time", type=float, default=2.0,
                        help="simulated seconds per IR-SIM run (default 2; IR-SIM is slow)")
    parser.add_argument("--mimics-time", type=float, default=60.0,
                        help="simulated seconds per mimics run (default 60)")
    parser.add_argument("--repeats", type=int, default=3,
                        help="timed runs per row, median reported (default 3)")
    parser.add_argument("--map", choices=["filled", "irsim"], default="filled",
                        help="IR-SIM's bitmap: Stage's cave_filled.png, the one mimics' "
                             "cave uses (default), or IR-SIM's packaged cave.png (outlines)")
    parser.add_argument("--no-logging", dest="logging", action="store_false",
                        help="do not record the mimics runs (default: recorded like "
                             "`mimics run`; IR-SIM keeps in-memory trajectories only)")
    parser.add_argument("--threads", type=int, default=None,
                        help="NUMBA_NUM_THREADS for the mimics runs (default: inherited)")
    parser.add_argument("--results", type=Path, default=RESULTS,
                        help="results file to merge into (default benchmarks/results.json)")
    parser.add_argument("--child", default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:  # one mimics row, in a fresh process
        child_main(args.child)
        return

    irsim = require_irsim()
    setup = cave_setup(args.map, irsim)
    print(f"Cave, 100 robots, 180-beam 8 m lidar: IR-SIM {irsim.__version__} for "
          f"{args.time:g} s simulated ({Path(setup['bitmap']).name}), mimics for "
          f"{args.mimics_time:g} s (logging {'on' if args.logging else 'off'}); median of "
          f"{args.repeats}")
    peer = measure_irsim(irsim, setup, args.time, args.repeats)
    rows = [peer, *measure_mimics(args)]
    for row in rows:  # robots moving and scanning, on average (mimics deactivates
        # collided and deadlocked robots; IR-SIM's stopped robots keep scanning)
        row["mean_active"] = row["robot_steps"] / max(row["steps"], 1)
    for row in rows[1:]:
        row["ratio_sim_speed"] = row["sim_speed"] / peer["sim_speed"]
        row["ratio_cpu_sim_speed"] = row["cpu_sim_speed"] / peer["cpu_sim_speed"]
        row["ratio_rays_per_s"] = row["rays_per_s"] / peer["rays_per_s"]
    print()
    print("  ".join(f"{HEADERS.get(c, c):>14}" for c in COLUMNS))
    print_table("", [{c: r.get(c) for c in COLUMNS} for r in rows], COLUMNS, header=False)
    print()
    for row in rows[1:]:
        print(f"mimics {row['form']} / IR-SIM: {row['ratio_sim_speed']:.0f}x s_sim/s "
              f"(wall), {row['ratio_cpu_sim_speed']:.0f}x per CPU second, "
              f"{row['ratio_rays_per_s']:.0f}x rays/s")
    print(f"start scans, IR-SIM vs mimics: {peer['scan_fraction_within_0_1m']:.1%} of beams "
          f"within 0.1 m (90th percentile of |difference| "
          f"{peer['scan_p90_abs_diff_m']:.3f} m)")
    print(f"(load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs: timings are "
          "noisy on a shared machine)")
    meta = {"irsim_time": args.time, "mimics_time": args.mimics_time,
            "repeats": args.repeats, "map": args.map, "logging": args.logging,
            "threads_requested": args.threads, "cpus": os.cpu_count(),
            "irsim_version": irsim.__version__, "machine": platform.platform(),
            "python": platform.python_version(),
            "measured": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    save("peers_irsim", {"meta": meta, "rows": rows}, args.results)


if __name__ == "__main__":
    main()
