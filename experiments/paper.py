"""Re-run the paper's experiments with one command each, beside the paper's figures.

    python experiments/paper.py figure2  [--quick] [--out DIR] [--workers N]
    python experiments/paper.py cave     [--quick] [--out DIR] [--workers N]
    python experiments/paper.py hospital [--quick] [--out DIR] [--workers N]

Each runs a battery with mimics' own runner (``figure2``:
``benchmarks/paper_figure2.toml``, the others ``experiments/NAME.toml``),
draws the battery's figures (``mimics battery plot``: outcomes, and for
``figure2`` the wall time against the number of robots, the paper's Figure 2)
and writes ``comparison.md`` into the battery folder: each of the paper's
figures for that experiment beside ours, and the collisions, deadlocks and
livelocks counted over all runs. ``--quick`` runs a small version (fewer
robots, seeds and seconds) to try the pipeline, not figures to quote.
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
BATTERIES = {"figure2": ROOT / "benchmarks" / "paper_figure2.toml",
             "cave": ROOT / "experiments" / "cave.toml",
             "hospital": ROOT / "experiments" / "hospital.toml"}
QUICK = {"figure2": {"seeds": 2, "robots": [1, 5, 10]},
         "cave": {"seeds": 2, "time": 20.0},
         "hospital": {"seeds": 1, "time": 2.0}}
# The paper's figures (section 4, 5.1, 5.2): (what, value, unit, where it comes from).
PAPER: dict[str, list[tuple[str, float, str, str]]] = {
    "figure2": [("mean wall time of a 21.8 s run, MATLAB on an i7-5500U", 28.92 * 3600 / 5400,
                 "s", "28.92 h for 5,400 runs (N = 1..60, 30 seeds, 3 representation times)")],
    "cave": [("MiMicS (MATLAB R2016a, i7-5500U): wall time of a 600 s run", 919.50, "s",
              "919.50 ± 15.33 s, 0.65 s_sim/s"),
             ("Stage 4 on ROS Kinetic (same machine): wall time of a 600 s run", 94.37, "s",
              "94.37 ± 4.88 s, 6.35 s_sim/s"),
             ("collisions in 30 runs (MiMicS)", 0.0, "", "section 5.1")],
    "hospital": [("MiMicS (MATLAB, i7-5500U): wall time of a 600 s run", 15.09 * 3600, "s",
                  "15.09 ± 0.018 h, 0.011 s_sim/s")],
}


def battery_spec(name: str, quick: bool) -> Any:
    """The experiment's battery spec, shrunk by ``--quick``."""
    from mimics.batteries.spec import spec_from_dict

    path = BATTERIES[name]
    data = tomllib.loads(path.read_text())
    if quick:
        changes = QUICK[name]
        data["battery"]["seeds"] = changes["seeds"]
        if "time" in changes:
            data["battery"]["time"] = changes["time"]
        if "robots" in changes:
            data["scenarios"][0]["robots"] = changes["robots"]
    return spec_from_dict(data, base=path.parent, source=str(path))


def comparison(name: str, table: pd.DataFrame) -> str:
    """Markdown: the paper's figures beside this battery's, and the misbehaviour counts."""
    from mimics.batteries.report import mean_ci95

    done = table[table["state"] == "done"]
    wall = done["wall_time"].to_numpy(np.float64)
    sim = done["sim_time"].to_numpy(np.float64)
    mean, half = mean_ci95(wall)
    lines = [f"# {name}: the paper beside mimics", "",
             f"{len(done)} of {len(table)} runs finished; {sim.mean():g} s simulated per run "
             f"on average.", "", "| paper | its figure | mimics | paper / mimics |",
             "|---|---|---|---|"]
    for what, value, unit, source in PAPER[name]:
        if unit == "s":
            ratio = f"{value / mean:,.0f}x" if mean > 0 else "-"
            lines.append(f"| {what} | {source} | {mean:.3g} ± {half:.2g} s, "
                         f"{sim.mean() / mean:.3g} s_sim/s | {ratio} |")
        else:
            lines.append(f"| {what} | {value:g} ({source}) | "
                         f"{int(done['collisions'].sum())} in {len(done)} runs | |")
    span = float(table["ended"].max() - table["started"].min())
    lines += ["", f"The whole battery: {len(table)} runs in {span:.1f} s of wall time "
                  f"({span / max(len(table), 1) * 1000:.1f} ms a run, workers and recording "
                  f"included)."]
    if name == "figure2":
        lines += ["", _linearity(done)]
    totals = {c: int(done[c].sum()) for c in ("collisions", "deadlocks", "livelocks", "escaped")}
    lines += ["", "Over all finished runs: " + ", ".join(f"{v} {k}" for k, v in totals.items())
              + ".", ""]
    return "\n".join(lines)


def _linearity(done: pd.DataFrame) -> str:
    """The paper's claim for Figure 2: wall time grows linearly with the robots."""
    means = done.groupby("robots")["wall_time"].mean()
    if len(means) < 3:
        return "Too few team sizes to fit a line."
    robots, wall = means.index.to_numpy(np.float64), means.to_numpy(np.float64)
    slope, intercept = np.polyfit(robots, wall, 1)
    fitted = slope * robots + intercept
    r2 = 1 - np.sum((wall - fitted) ** 2) / max(np.sum((wall - wall.mean()) ** 2), 1e-300)
    return (f"Linear fit of the mean wall time against the robots: {1000 * slope:.3g} ms per "
            f"robot, {intercept:.3g} s offset, R² = {r2:.3f} (the paper: linear).")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("experiment", choices=sorted(BATTERIES))
    parser.add_argument("--quick", action="store_true", help="a small version of the experiment")
    parser.add_argument("--out", type=Path, help="battery folder [default: experiments/runs/NAME]")
    parser.add_argument("--workers", type=int, default=None, help="local worker processes")
    args = parser.parse_args(argv)

    from mimics.batteries.driver import run_battery
    from mimics.batteries.report import runs_table
    from mimics.interfaces.plots import battery_plots

    out = args.out or ROOT / "experiments" / "runs" / args.experiment
    run_battery(battery_spec(args.experiment, args.quick), out, workers=args.workers)
    table = runs_table(out)
    written, skipped = battery_plots(out)
    text = comparison(args.experiment, table)
    (out / "comparison.md").write_text(text)
    print(text)
    for path in written:
        print(f"figure: {path}")
    for reason in skipped:
        print(f"no figure: {reason}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
