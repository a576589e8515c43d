"""The Cave tiled 1x, 4x (2x2) and 16x (4x4): is the cost per robot-step flat?

    python benchmarks/cave_tiling.py [--tiles 1 2 4] [--forms team per-robot] [--time 20]
                                     [--repeats 3] [--no-logging] [--threads N] [--quick]

Each tile is a copy of the Cave: its wall segments and its 100 Pioneer2DX
(Stage's start poses) shifted by the tile's offset, so that the robot density
per tile is the same and a k x k world has k^2 times the segments and robots.
Tiles touch: the walls along a shared edge are kept, both copies (the map
has exactly k^2 times the segments, and each tile stays a closed cave). Runs
``deployment_team`` (and ``deployment``, the per-robot form, with ``--forms``),
each world in a fresh process, recorded like ``mimics run`` unless
``--no-logging``. Prints microseconds per robot-step per tiling and the ratio
16x / 1x (issue target: flat within 1.5x); merges the figures into
benchmarks/results.json under ``cave_tiling``.
"""

from __future__ import annotations

import dataclasses
from typing import Any

import common
import numpy as np

FORMS = {"team": "deployment_team", "per-robot": "deployment"}
TARGET_RATIO = 1.5  # us per robot-step, 16x over 1x, at most


def tiled_cave(tiles: int) -> Any:
    """The built-in Cave repeated ``tiles`` x ``tiles`` times (walls and robots)."""
    from mimics.catalog import load_scenario
    from mimics.world.maps import Map

    base = load_scenario("cave")
    if tiles == 1:
        return base
    xmin, ymin, xmax, ymax = base.map.bounds
    width, height = xmax - xmin, ymax - ymin
    offsets = [(i * width, j * height) for j in range(tiles) for i in range(tiles)]
    segments = np.vstack([base.map.segments + np.array([dx, dy, dx, dy])
                          for dx, dy in offsets])
    stages = np.vstack([base.stages + np.array([dx, dy, 0.0, 0.0]) for dx, dy in offsets])
    goals = np.vstack([base.goals + np.array([dx, dy]) for dx, dy in offsets])
    bounds = (xmin, ymin, xmin + tiles * width, ymin + tiles * height)
    world = Map(segments, bounds, name=f"cave {tiles}x{tiles}")
    return dataclasses.replace(base, map=world, stages=stages, goals=goals,
                               type_index=np.tile(base.type_index, len(offsets)),
                               name=f"cave_{tiles}x{tiles}")


def build(spec: dict[str, Any]) -> Any:
    """The child's scenario: the Cave tiled ``spec["tiles"]`` times per side."""
    return tiled_cave(int(spec["tiles"]))


def main() -> None:
    parser = common.benchmark_parser(__doc__, time=20.0, quick_time=2.0)
    parser.add_argument("--tiles", type=int, nargs="+", default=[1, 2, 4],
                        help="tiles per side (1, 2, 4: 1x, 4x, 16x the Cave)")
    parser.add_argument("--forms", nargs="+", choices=list(FORMS), default=list(FORMS))
    args = common.parse_or_serve_child(parser, build)
    if args is None:
        return
    print(f"cave tiled {', '.join(f'{k * k}x' for k in args.tiles)} (shared walls kept), "
          f"{args.time:g} s simulated per run, median of {args.repeats}, logging "
          f"{'on' if args.logging else 'off'}")
    columns = ["form", "tiles", "robots", "segments", "sim_speed", "robot_steps_per_s",
               "us_per_robot_step", "rays_per_s", "peak_rss_mb", "threads", "logging"]
    common.print_table("", [], columns)
    rows = [common.measured_row(__file__, args, "cave_tiling", form, columns,
                                extra={"tiles": f"{k * k}x", "algorithm": FORMS[form]},
                                algorithm=FORMS[form], tiles=k)
            for form in args.forms for k in args.tiles]
    ratios = []
    for form in args.forms:
        mine = sorted((r for r in rows if r["form"] == form), key=lambda r: r["robots"])
        small, big = mine[0], mine[-1]
        ratio = big["us_per_robot_step"] / small["us_per_robot_step"]
        ratios.append({"benchmark": "cave_tiling", "form": form, "small": small["tiles"],
                       "big": big["tiles"], "ratio": ratio, "target": TARGET_RATIO,
                       "target_met": ratio <= TARGET_RATIO})
        print(f"  {form:>9}: us per robot-step {big['tiles']} / {small['tiles']} = {ratio:.2f} "
              f"(target <= {TARGET_RATIO:g}): {'met' if ratio <= TARGET_RATIO else 'NOT met'}")
    common.save_measured(args, "cave_tiling", rows, ratios=ratios, shared_walls="kept")


if __name__ == "__main__":
    main()
