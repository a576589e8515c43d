"""What the views cost: live view on the Cave, replay export of a Cave run, big teams.

    python benchmarks/view_costs.py [--time 60] [--repeats 3] [--keep DIR]

Bars (issue #6):

* the live view at ``1s`` (off-screen Agg canvas) costs under 20% of the run
  time of the Cave deployment (100 robots, ``--time`` simulated seconds): the
  wall time spent inside the view's hooks, divided by the run time without a
  view (the difference of two run times is also printed; it is noisier);
* exporting the replay of that run to MP4 at 10 frames per simulated second
  (``fps=10, speed=1``: 601 frames for 60 s) takes under 60 s.

Also measured: the live view at ``step`` and ``10s`` (the paper's other two
representation times), the export with one robot's beams recomputed, a GIF
export, and one frame of 2,000 robots. Without the ``cave`` scenario or the
``deployment`` algorithm it falls back to ``line`` with ``go_to_goal`` and
says so. Prints the figures and writes ``benchmarks/results/view_costs.json``.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from common import add_run_options, write_json

from mimics.catalog import list_algorithms, list_scenarios
from mimics.engine.state import Status
from mimics.interfaces.live_view import LiveView
from mimics.interfaces.render import WorldRenderer
from mimics.interfaces.replay import export_replay
from mimics.records.runner import prepare, run_to_folder

RESULTS = Path(__file__).with_name("results") / "view_costs.json"


def workload() -> tuple[str, str, dict[str, Any]]:
    """The Cave deployment if both exist, else the line scenario with 100 robots."""
    scenarios = {name for name, _ in list_scenarios()}
    algorithms = {name for name, _ in list_algorithms()}
    if "cave" in scenarios and "deployment" in algorithms:
        return "cave", "deployment", {}
    print("cave scenario or deployment algorithm missing: using line / go_to_goal, 100 robots")
    return "line", "go_to_goal", {"robots": 100}


class TimedView:
    """Wraps a view and adds up the wall time spent in its hooks (immune to machine noise
    that the difference of two run times is not)."""

    def __init__(self, view: LiveView) -> None:
        self.view = view
        self.seconds = 0.0

    def _timed(self, hook: str, *args: Any) -> None:
        start = time.perf_counter()
        getattr(self.view, hook)(*args)
        self.seconds += time.perf_counter() - start

    def on_start(self, sim: Any) -> None:
        self._timed("on_start", sim)

    def on_step(self, sim: Any) -> None:
        self._timed("on_step", sim)

    def on_end(self, sim: Any, result: Any) -> None:
        self._timed("on_end", sim, result)


def timed_run(scenario: str, algorithm: str, params: dict[str, Any], sim_time: float,
              view: TimedView | None = None) -> tuple[float, float]:
    """Wall time of one run (s), and the simulated time it covered."""
    sim = prepare(scenario, algorithm, time=sim_time, seed=1, params=dict(params),
                  observers=() if view is None else (view,))
    start = time.perf_counter()
    sim.run()
    return time.perf_counter() - start, sim.state.time


def live_view_costs(scenario: str, algorithm: str, params: dict[str, Any], sim_time: float,
                    repeats: int) -> dict[str, Any]:
    """Median wall time without a view and with each representation time (interleaved)."""
    timed_run(scenario, algorithm, params, 1.0)  # compile the kernels once
    walls: dict[str, list[float]] = {"off": [], "1s": [], "10s": [], "step": []}
    in_view: dict[str, list[float]] = {mode: [] for mode in walls}
    frames: dict[str, int] = {}
    covered = 0.0
    for attempt in range(repeats):
        for mode in walls:
            if mode == "step" and attempt > 0:
                continue  # the slowest; once is enough to show the paper's offset
            view = None if mode == "off" else TimedView(LiveView(mode, offscreen=True))
            wall, covered = timed_run(scenario, algorithm, params, sim_time, view)
            walls[mode].append(wall)
            in_view[mode].append(0.0 if view is None else view.seconds)
            frames[mode] = 0 if view is None else len(view.view.drawn_times)
    base = statistics.median(walls["off"])
    out: dict[str, Any] = {"sim_time": covered, "run_wall_s": base, "run_walls_s": walls["off"]}
    for mode in ("step", "1s", "10s"):
        wall = statistics.median(walls[mode])
        spent = statistics.median(in_view[mode])
        out[f"view_{mode}"] = {"wall_s": wall, "walls_s": walls[mode], "frames": frames[mode],
                               "in_view_s": spent, "in_view_fraction": spent / base,
                               "wall_overhead": (wall - base) / base,
                               "ms_per_frame": 1000 * spent / max(frames[mode], 1)}
    return out


def export_costs(scenario: str, algorithm: str, params: dict[str, Any], sim_time: float,
                 folder: Path) -> dict[str, Any]:
    """Record one run, then export its replay as MP4 (with and without beams) and GIF."""
    sim = prepare(scenario, algorithm, time=sim_time, seed=1, params=dict(params))
    run_dir = folder / "run"
    run_to_folder(sim, run_dir)
    # the folder's name only: it is temporary unless --keep, and a path names this machine
    out: dict[str, Any] = {"run_folder": run_dir.name}
    for name, options in (("mp4", {"video": folder / "replay.mp4"}),
                          ("mp4_beams_robot0", {"video": folder / "replay_beams.mp4",
                                                "robot_beams": 0}),
                          ("gif_speed4", {"gif": folder / "replay.gif", "speed": 4.0})):
        options = {"fps": 10.0, "speed": 1.0, **options}
        result = export_replay(run_dir, progress=False, **options)
        out[name] = {"frames": result.frames, "size": [result.width, result.height],
                     "wall_s": result.wall_time, "fps": options["fps"],
                     "speed": options["speed"],
                     "frames_per_s": result.frames / result.wall_time}
    return out


def big_team_frame(n: int = 2000, repeats: int = 10) -> dict[str, Any]:
    """Milliseconds per off-screen frame of ``n`` small robots on a 140 x 60 m map."""
    rng = np.random.default_rng(0)
    renderer = WorldRenderer.create(np.array([[0, 0, 140, 0], [0, 60, 140, 60]]),
                                    (0, 0, 140, 60), np.full(n, 0.05), np.full(n, 0.05))
    pose = np.column_stack([rng.uniform(0, 140, n), rng.uniform(0, 60, n),
                            rng.uniform(-np.pi, np.pi, n)])
    status = rng.integers(0, len(Status), n).astype(np.int8)
    trails = pose[:, None, :2] + np.cumsum(rng.normal(0, 0.05, (n, 7, 2)), axis=1)
    renderer.update(pose, status, 0.0, trails=trails)
    renderer.to_rgb()
    start = time.perf_counter()
    for k in range(repeats):
        pose[:, 0] += 0.01
        renderer.update(pose, status, 0.1 * k, trails=trails)
        renderer.to_rgb()
    return {"robots": n, "ms_per_frame": 1000 * (time.perf_counter() - start) / repeats}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    add_run_options(parser, time=60.0, repeats=3)
    parser.add_argument("--keep", type=Path, default=None,
                        help="keep the run folder and videos here")
    args = parser.parse_args()
    scenario, algorithm, params = workload()
    results: dict[str, Any] = {"scenario": scenario, "algorithm": algorithm, "params": params,
                               "machine": platform.processor() or platform.machine(),
                               "python": platform.python_version()}
    results["live_view"] = live_view_costs(scenario, algorithm, params, args.time, args.repeats)
    live = results["live_view"]
    print(f"{scenario} / {algorithm}: {live['sim_time']:g} s simulated, run without view "
          f"{live['run_wall_s']:.2f} s (median of {len(live['run_walls_s'])})")
    for mode in ("step", "1s", "10s"):
        v = live[f"view_{mode}"]
        print(f"  live view {mode:>4}: {v['frames']} frames, {v['in_view_s']:.2f} s in the "
              f"view = {100 * v['in_view_fraction']:.1f}% of the run "
              f"({v['ms_per_frame']:.1f} ms per frame, setup included); run with it "
              f"{v['wall_s']:.2f} s ({100 * v['wall_overhead']:+.1f}%)")
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.keep or Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        results["export"] = export_costs(scenario, algorithm, params, args.time, folder)
    for name, e in results["export"].items():
        if isinstance(e, dict):
            print(f"  export {name}: {e['frames']} frames {e['size'][0]}x{e['size'][1]} in "
                  f"{e['wall_s']:.1f} s ({e['frames_per_s']:.0f} frames/s)")
    results["big_team_frame"] = big_team_frame()
    print(f"  2000 robots: {results['big_team_frame']['ms_per_frame']:.1f} ms per frame")
    bars = {"live_view_1s_overhead_below_20pct": live["view_1s"]["in_view_fraction"] < 0.20,
            "export_600_frames_below_60s": results["export"]["mp4"]["wall_s"] < 60.0}
    results["bars"] = bars
    print("bars: " + ", ".join(f"{k}: {'ok' if v else 'MISSED'}" for k, v in bars.items()))
    write_json(RESULTS, results)
    print(f"wrote {RESULTS}")


if __name__ == "__main__":
    main()
