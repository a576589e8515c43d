"""The Cave with 45 to 720 beams per robot: does the cost grow linearly with the beams?

    python benchmarks/beam_scaling.py [--beams 45 90 180 360 720] [--form team|per-robot]
                                      [--time 20] [--repeats 3] [--no-logging] [--quick]

The Cave's 100 Pioneer2DX with the robot type's ranger set to ``--beams``
beams (same 180 degree field of view and 8 m range; a variant of the type made
with ``dataclasses.replace``), running ``deployment_team`` (or ``deployment``
with ``--form per-robot``). Each beam count runs in a fresh process, recorded
like ``mimics run`` unless ``--no-logging``. Prints microseconds per
robot-step against beams per robot, and the least-squares line
``us = a + b * beams`` with its R^2 (issue: cost against beams is linear).
Merges the figures into benchmarks/results.json under ``beam_scaling``.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import common
import numpy as np

FORMS = {"team": "deployment_team", "per-robot": "deployment"}


def cave_with_beams(beams: int) -> Any:
    """The built-in Cave, its robot type's ranger given ``beams`` beams."""
    from mimics.catalog import load_scenario

    base = load_scenario("cave")
    types = tuple(dataclasses.replace(t, ranger=dataclasses.replace(t.ranger, beams=beams))
                  for t in base.types)
    return dataclasses.replace(base, types=types, name=f"cave_{beams}_beams")


def build(spec: dict[str, Any]) -> Any:
    """The child's scenario: the Cave with ``spec["beams"]`` beams per robot."""
    return cave_with_beams(int(spec["beams"]))


def line_fit(x: list[float], y: list[float]) -> dict[str, float]:
    """Least-squares ``y = a + b x`` and its coefficient of determination R^2."""
    xs, ys = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    b, a = np.polyfit(xs, ys, 1)
    residual = float(np.sum((ys - (a + b * xs)) ** 2))
    total = float(np.sum((ys - ys.mean()) ** 2))
    return {"intercept_us": float(a), "us_per_beam": float(b),
            "r2": 1.0 - residual / total if total > 0 else 1.0}


def main() -> None:
    parser = common.benchmark_parser(__doc__, time=20.0, quick_time=2.0)
    parser.add_argument("--beams", type=int, nargs="+", default=[45, 90, 180, 360, 720])
    parser.add_argument("--form", choices=list(FORMS), default="team")
    args = common.parse_or_serve_child(parser, build)
    if args is None:
        return
    algorithm = FORMS[args.form]
    print(f"cave, 100 Pioneer2DX, {algorithm}, beams {args.beams}, {args.time:g} s simulated "
          f"per run, median of {args.repeats}, logging {'on' if args.logging else 'off'}")
    columns = ["form", "robots", "beams_per_robot", "sim_speed", "robot_steps_per_s",
               "us_per_robot_step", "rays_per_s", "peak_rss_mb", "threads", "logging"]
    common.print_table("", [], columns)
    rows = [common.measured_row(__file__, args, "beam_scaling", args.form, columns,
                                extra={"algorithm": algorithm}, algorithm=algorithm, beams=beams)
            for beams in args.beams]
    fit = line_fit([r["beams_per_robot"] for r in rows], [r["us_per_robot_step"] for r in rows])
    print(f"  least squares: us per robot-step = {fit['intercept_us']:.2f} + "
          f"{fit['us_per_beam']:.4f} * beams, R^2 = {fit['r2']:.4f}")
    for row in rows:
        row["fit_us"] = fit["intercept_us"] + fit["us_per_beam"] * row["beams_per_robot"]
    common.save_measured(args, "beam_scaling", rows, fit=fit)


if __name__ == "__main__":
    main()
