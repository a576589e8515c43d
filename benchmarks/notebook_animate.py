"""What a notebook's ``run.animate()`` costs: a 60 s Cave deployment run, replayed inline.

    python benchmarks/notebook_animate.py [--time 60] [--repeats 5]

Bar (issue #42): ``.animate()`` of a 60 s Cave run (100 robots, ``deployment``)
with its defaults (640 pixels; 10 fps; at most 201 frames, so 4x for 60 s) is
ready in under 5 s and under 10 MB. The run is simulated once, in memory, as
``mimics.simulate`` does (not timed); then ``animate()`` is timed ``--repeats``
times after one warm-up (Matplotlib's and ffmpeg's first start), and the
medians of the time and of the inline size (the ``<video>`` element's HTML,
base64 included) are printed, with the simulation's own speed for reference
(s_sim/s and robot-steps/s). Writes ``benchmarks/results/notebook_animate.json``.
"""

from __future__ import annotations

import argparse
import platform
import statistics
import time
from pathlib import Path

from common import add_run_options, speeds_text, write_json

import mimics

RESULTS = Path(__file__).with_name("results") / "notebook_animate.json"
SECONDS_BAR = 5.0
MB_BAR = 10.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_run_options(parser, time=60.0)
    parser.add_argument("--repeats", type=int, default=5, help="timed animate() calls")
    args = parser.parse_args()

    began = time.perf_counter()
    run = mimics.simulate("cave", "deployment", time=args.time, seed=1)
    simulated = time.perf_counter() - began
    summary = run.summary()
    robot_steps = len(run.trajectory) - summary["robots"]  # a row per robot-step, + step 0
    print(f"run: cave / deployment, {summary['robots']} robots, {summary['sim_time']:g} s "
          f"simulated in {simulated:.2f} s wall (first call includes start-up); engine "
          f"{speeds_text(summary['sim_speed'], robot_steps / summary['wall_time'], 1)}")

    run.animate()  # warm-up: Matplotlib, the renderer's fonts, ffmpeg's first start
    seconds, megabytes, frames = [], [], 0
    for _ in range(args.repeats):
        began = time.perf_counter()
        animation = run.animate()
        html = animation._repr_html_()
        seconds.append(time.perf_counter() - began)
        megabytes.append(len(html.encode()) / 1e6)
        frames = animation.frames
    median_s, median_mb = statistics.median(seconds), statistics.median(megabytes)
    print(f"animate(): {frames} frames at {animation.fps:g} fps, {animation.speed:g}x, "
          f"{animation.width}x{animation.height} px")
    print(f"  time  median {median_s:.2f} s (min {min(seconds):.2f}, max {max(seconds):.2f}, "
          f"{args.repeats} runs)  bar {SECONDS_BAR:g} s: "
          f"{'OK' if median_s < SECONDS_BAR else 'OVER'}")
    print(f"  size  median {median_mb:.2f} MB inline (video {animation.megabytes:.2f} MB)  "
          f"bar {MB_BAR:g} MB: {'OK' if median_mb < MB_BAR else 'OVER'}")
    write_json(RESULTS, {
        "time_s": args.time, "robots": summary["robots"], "frames": frames,
        "speed": animation.speed, "size_px": [animation.width, animation.height],
        "animate_seconds": seconds, "animate_seconds_median": median_s,
        "inline_mb": megabytes, "inline_mb_median": median_mb,
        "machine": platform.platform(), "python": platform.python_version(),
    })


if __name__ == "__main__":
    main()
