"""Command-line front ends for maps and map data: ``mimics map ...`` and ``mimics data ...``.

Two Typer sub-apps that the main CLI mounts::

    app.add_typer(maps.app, name="map")
    app.add_typer(maps.data_app, name="data")

Every error a user can cause (an unreadable file, a bad option, no network)
is printed as one line ``mimics: error: ...`` on stderr and exits with status 2.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer

from mimics.interfaces.cli.output import fail as _fail
from mimics.interfaces.cli.output import say as _say
from mimics.world.errors import MimicsError

DPI = 100  # pixels per inch of `map show`'s image

app = typer.Typer(help="Import maps from drawings and images, and draw them.",
                  no_args_is_help=True, add_completion=False, rich_markup_mode=None,
                  pretty_exceptions_enable=False)
data_app = typer.Typer(help="Get map data that mimics does not ship (the Stage benchmark maps).",
                       no_args_is_help=True, add_completion=False, rich_markup_mode=None,
                       pretty_exceptions_enable=False)


@data_app.callback()
def data_callback() -> None:
    """Get map data that mimics does not ship (the Stage benchmark maps)."""






@app.command("import")
def import_command(
    file: Annotated[Path, typer.Argument(
        help="A drawing or image: .svg, .png/.pgm/.bmp, ROS .yaml, or a plain/.toml/.json map.")],
    out: Annotated[Path, typer.Option(help="Map file to write: .txt, .map, .segments, .toml or "
                                           ".json.")],
    scale: Annotated[float | None, typer.Option(
        help="SVG: metres per SVG user unit [default: the drawing's physical units].")] = None,
    resolution: Annotated[float | None, typer.Option(
        help="Images: metres per pixel [default: 0.05].")] = None,
    origin: Annotated[tuple[float, float] | None, typer.Option(
        help="Images: world position X Y of the bottom-left corner (m).")] = None,
    tolerance: Annotated[float | None, typer.Option(
        help="Simplification tolerance in metres [default: one pixel; SVG curves: 1/1000 of "
             "the drawing].")] = None,
    size: Annotated[tuple[float, float] | None, typer.Option(
        help="Stage bitmaps: world size W H (m) of the obstacle pixels' bounding box.")] = None,
    center: Annotated[tuple[float, float] | None, typer.Option(
        help="Stage bitmaps: centre X Y of the world (m) [default: 0 0].")] = None,
) -> None:
    """Turn a drawing or an occupancy image into a map of wall segments."""
    from mimics.world.map_files import load_map, save_map
    from mimics.world.output_paths import check_outputs

    given: dict[str, Any] = {"scale": scale, "resolution": resolution, "origin": origin,
                             "tolerance": tolerance, "size": size, "center": center}
    options = {k: v for k, v in given.items() if v is not None}
    if "center" in options and "size" not in options:
        raise _fail("--center applies to Stage bitmaps: give --size W H too")
    try:
        check_outputs({"--out": out}, {"the map file": file})  # before reading it
        loaded = load_map(file, **options)
        save_map(loaded, out)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    xmin, ymin, xmax, ymax = loaded.bounds
    _say(f"wrote {out}: {len(loaded.segments)} segments, bounds ({xmin:g}, {ymin:g}) to "
         f"({xmax:g}, {ymax:g})")


@app.command("show")
def show_command(
    map: Annotated[str, typer.Argument(
        help="A map file (any form `mimics map import` reads) or a built-in map: stage:cave, "
             "stage:hospital.")],
    out: Annotated[Path, typer.Option(help="Image to write (.png, .svg, .pdf).")],
    width: Annotated[float, typer.Option(help="Width of the figure in inches.")] = 8.0,
) -> None:
    """Draw a map's walls and bounds to an image file."""
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.collections import LineCollection
    from matplotlib.figure import Figure
    from matplotlib.patches import Rectangle

    from mimics.world.limits import MAX_IMAGE_SIDE, check_image_side
    from mimics.world.map_files import load_map
    from mimics.world.output_paths import check_outputs

    if not 0 < width <= MAX_IMAGE_SIDE / DPI:
        raise _fail(f"--width: expected a positive number of inches, at most "
                    f"{MAX_IMAGE_SIDE / DPI:g} ({MAX_IMAGE_SIDE} px at {DPI} dpi), got {width:g}")
    try:
        if Path(map).exists():  # a built-in name (stage:cave) is no file to overwrite
            check_outputs({"--out": out}, {"the map file": map})
        loaded = load_map(map)
        xmin, ymin, xmax, ymax = loaded.bounds
        aspect = (ymax - ymin) / (xmax - xmin)
        # a map far taller than wide would make an image no renderer can allocate
        check_image_side("--width: the image's height", width * aspect * DPI + 60)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    figure = Figure(figsize=(width, max(2.0, width * aspect + 0.6)))
    axes = figure.add_subplot()
    axes.add_patch(Rectangle((xmin, ymin), xmax - xmin, ymax - ymin, fill=False, ls="--",
                             lw=0.8, ec="0.6"))
    axes.add_collection(LineCollection(loaded.segments.reshape(-1, 2, 2), colors="k",
                                       linewidths=1.0))
    axes.set_xlim(xmin, xmax)
    axes.set_ylim(ymin, ymax)
    axes.set_aspect("equal")
    axes.set_xlabel("x (m)")
    axes.set_ylabel("y (m)")
    axes.set_title(f"{loaded.name}: {len(loaded.segments)} segments")
    try:
        figure.savefig(out, dpi=DPI, bbox_inches="tight")
    except (OSError, ValueError) as exc:
        raise _fail(f"cannot write {out}: {exc}") from None
    _say(f"wrote {out}")


@data_app.command("get")
def get_command(
    what: Annotated[str, typer.Argument(help="The data set to get: stage.")],
    url: Annotated[str | None, typer.Option(
        help="Base URL of the repository to download from [default: Stage on GitHub].")]
    = None,
    dest: Annotated[Path | None, typer.Option(
        help="Folder to write [default: stage/ in the data folder: MIMICS_DATA or the user "
             "data folder].")] = None,
) -> None:
    """Download a data set (the Stage Cave and Hospital maps and worlds, GPL-2.0)."""
    from rich.progress import BarColumn, DownloadColumn, Progress, TextColumn

    from mimics.world.data_folder import STAGE, download_folder
    from mimics.world.stage_data import STAGE_BASE_URL, download_stage

    if what != "stage":
        raise _fail(f"unknown data set {what!r} (expected: stage)")
    folder = dest if dest is not None else download_folder() / STAGE
    columns = (TextColumn("{task.description}"), BarColumn(), DownloadColumn())
    with Progress(*columns, transient=True) as bar:
        tasks: dict[str, Any] = {}

        def progress(name: str, received: int, total: int | None) -> None:
            if name not in tasks:
                tasks[name] = bar.add_task(name, total=total)
            bar.update(tasks[name], completed=received, total=total)

        try:
            paths = download_stage(folder, base_url=url or STAGE_BASE_URL, progress=progress)
        except MimicsError as exc:
            bar.stop()
            raise _fail(str(exc)) from None
    _say(f"Stage data ({len(paths)} files, checksums verified) in {folder}")
