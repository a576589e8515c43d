"""Regenerate the documentation's pictures from real runs, with the project's own plotting.

Every built-in scenario (and so every built-in map) is run with a fitting
built-in algorithm and plotted with :func:`mimics.interfaces.plots.plot_run`;
the tutorials' run and battery are re-run from their snippet files. Writes
``docs/images/*.png``; run from the project root::

    python docs/make_figures.py            # all figures (the Hospital takes a minute)
    python docs/make_figures.py --only circle_swap corridor

The PNGs are reduced to a 64-colour palette so that each stays small.
"""

from __future__ import annotations

import argparse
import os
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from PIL import Image
from PIL.PngImagePlugin import PngInfo

import mimics
from mimics.interfaces.plots import battery_table, plot_outcomes, plot_run

DOCS = Path(__file__).resolve().parent
IMAGES = DOCS / "images"
SNIPPETS = DOCS / "snippets"

# scenario -> (algorithm, simulated seconds, robots or None for the default)
SCENARIO_RUNS: dict[str, tuple[str, float, int | None]] = {
    "line": ("go_to_goal_team", 25.0, 10),
    "circle_swap": ("wall_aware", 40.0, None),
    "corridor": ("wall_aware", 220.0, None),
    "obstacle_room": ("deployment_team", 60.0, None),
    "cave": ("deployment_team", 60.0, None),
    "hospital": ("deployment_team", 30.0, None),
}


def shrink(path: Path, title: str | None = None) -> Path:
    """Quantise a PNG to a small palette (plots use few colours); ``title``, the plot's
    title, is kept in the PNG's ``Title`` text so that a test can compare it with a run."""
    with Image.open(path) as image:
        small = image.convert("RGB").quantize(colors=64, method=Image.Quantize.MEDIANCUT)
    info = PngInfo()
    if title is not None:
        info.add_text("Title", title)
    small.save(path, optimize=True, pnginfo=info)
    return path


def plot_title(run: Path) -> str:
    """The title :func:`plot_run` gives the run's figure."""
    import matplotlib.pyplot as plt

    figure = plot_run(run, None, width_px=720, height_px=560)
    title = figure.axes[0].get_title()
    plt.close(figure)
    return title


def run_snippet_line(snippet: Path, work: Path) -> None:
    """Run the first line of a tutorial's shell snippet in ``work``, as the reader does."""
    from mimics.interfaces.cli import main as cli

    line = next(ln for ln in snippet.read_text().splitlines() if ln.strip())
    words = shlex.split(line)
    assert words[0] == "mimics", line
    here = Path.cwd()
    os.chdir(work)
    try:
        if cli(words[1:]) != 0:
            raise SystemExit(f"{snippet.name}: {line} failed")
    finally:
        os.chdir(here)


def scenario_figure(name: str, work: Path) -> Path:
    algorithm, time, robots = SCENARIO_RUNS[name]
    folder = work / name
    mimics.simulate(name, algorithm, robots=robots, time=time, seed=1, out=folder)
    width, height = mimics.load_run(folder).scenario.map.size
    # about as tall as the map (plus room for the title and axes), within limits
    height_px = int(min(560, max(260, 560 * height / width + 100)))
    return shrink(plot_run(folder, IMAGES / f"scenario_{name}.png", width_px=720,
                           height_px=height_px))


def tutorial_figures(work: Path) -> list[Path]:
    """The first tutorial's run of my_algo.py and the second's battery outcomes."""
    # the page's own command, on the page's own algorithm: the figure is the reader's run
    shutil.copy(SNIPPETS / "first_algorithm" / "my_algo.py", work / "my_algo.py")
    run_snippet_line(SNIPPETS / "first_algorithm" / "run_my_algo.sh", work)
    run = work / "runs" / "mine"
    written = [shrink(plot_run(run, IMAGES / "tutorial_my_algo.png", width_px=720,
                               height_px=560), plot_title(run))]
    battery = work / "night"
    subprocess.run([sys.executable, "-m", "mimics", "battery", "run",
                    str(SNIPPETS / "first_battery" / "battery.toml"), "--out", str(battery),
                    "--workers", "2", "--no-progress"], check=True, stdout=subprocess.DEVNULL)
    out = IMAGES / "tutorial_battery_outcomes.png"
    written.append(shrink(plot_outcomes(battery_table(battery), out, width_px=900,
                                        height_px=450)))
    return written


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", nargs="*", help="scenarios (or 'tutorial') to redo")
    args = parser.parse_args(argv)
    wanted = args.only or [*SCENARIO_RUNS, "tutorial"]
    IMAGES.mkdir(exist_ok=True)
    os.environ.setdefault("MPLBACKEND", "Agg")
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for name in wanted:
            paths = tutorial_figures(work) if name == "tutorial" else [scenario_figure(name, work)]
            for path in paths:
                print(f"wrote {path.relative_to(DOCS.parent)} ({path.stat().st_size // 1024} KB)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
