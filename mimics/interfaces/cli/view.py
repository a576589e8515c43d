"""Command-line front ends of the views: `mimics replay`, `mimics plot`, `mimics battery plot`.

Plain Typer command functions; the main CLI registers them::

    app.command("replay")(replay_command)
    app.command("plot")(plot_command)
    battery_app.command("plot")(battery_plot_command)

Every error a user can cause (not a run folder, a truncated trajectory, an
unwritable output, no display for a window) is printed as one line
``mimics: error: ...`` on stderr and exits with status 2.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from mimics.interfaces.cli.output import fail as _fail
from mimics.interfaces.cli.output import say as _say
from mimics.world.errors import MimicsError


def replay_command(
    run: Annotated[Path, typer.Argument(help="A run folder (written by `mimics run`).")],
    video: Annotated[Path | None, typer.Option(
        help="Write the replay to this video (.mp4, .mkv, .mov, .avi) instead of a window.")]
    = None,
    gif: Annotated[Path | None, typer.Option(help="Write the replay to this animated .gif.")]
    = None,
    fps: Annotated[float, typer.Option(help="Frames per second.")] = 10.0,
    speed: Annotated[float, typer.Option(
        help="Simulated seconds per second; frames are SPEED/FPS simulated seconds apart.")]
    = 1.0,
    robot_beams: Annotated[int | None, typer.Option(
        help="Draw the laser beams of this robot (recomputed from the logged poses).")] = None,
    trail: Annotated[float, typer.Option(help="Seconds of trail behind each robot.")] = 5.0,
    width: Annotated[int, typer.Option(help="Pixels of the longer side of the map.")] = 800,
    progress: Annotated[bool, typer.Option(help="Show a progress bar while exporting.")]
    = True,
) -> None:
    """Replay a finished run in a window (play/pause, time and speed sliders), or export it.

    With --video or --gif no display is needed: frames are drawn off screen
    and encoded with the ffmpeg bundled with imageio.
    """
    from mimics.interfaces.live_view import has_display
    from mimics.interfaces.replay import ReplayWindow, export_replay, open_run, replay_data
    from mimics.records.layout import run_records
    from mimics.world.output_paths import check_outputs

    try:
        check_outputs({"--video": video, "--gif": gif}, {"the run folder": run_records(run)})
        if video is not None or gif is not None:
            done = export_replay(run, video=video, gif=gif, fps=fps, speed=speed,
                                 robot_beams=robot_beams, trail=trail, width_px=width,
                                 progress=progress)
            outputs = ", ".join(str(p) for p in done.paths)
            _say(f"wrote {outputs}: {done.frames} frames of {done.width}x{done.height} at "
                 f"{fps:g} fps, {speed:g} simulated s per s ({done.wall_time:.1f} s)")
            return
        if not has_display():
            raise MimicsError("no display to show the replay: export it with --video run.mp4 "
                              "or --gif run.gif")
        if not fps > 0 or not speed > 0:
            raise MimicsError(f"fps and speed must be positive, got fps={fps}, speed={speed}")
        window = ReplayWindow(replay_data(open_run(run)), fps=fps, speed=speed,
                              robot_beams=robot_beams, trail=trail)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    window.show()


def plot_command(
    run: Annotated[Path, typer.Argument(help="A run folder (written by `mimics run`).")],
    out: Annotated[Path | None, typer.Option(help="PNG to write [default: RUN/run.png].")]
    = None,
    width: Annotated[int, typer.Option(help="Image width in pixels.")] = 1000,
    height: Annotated[int, typer.Option(help="Image height in pixels.")] = 800,
) -> None:
    """Plot a run: trajectories over the map, where robots stopped and why, a legend."""
    from mimics.interfaces.plots import plot_run
    from mimics.records.layout import run_records
    from mimics.world.output_paths import check_outputs

    try:
        check_outputs({"--out": out}, {"the run folder": run_records(run)})
        path = plot_run(run, out if out is not None else run / "run.png", width_px=width,
                        height_px=height)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    _say(f"wrote {path}")


def battery_plot_command(
    directory: Annotated[Path, typer.Argument(help="A battery folder.")],
    out: Annotated[Path | None, typer.Option(help="Folder for the PNGs [default: DIR/plots].")]
    = None,
) -> None:
    """Plot a battery: outcomes, time to goal per run, arrival curves, wall time vs robots.

    Writes outcomes.png (robot outcomes and run statuses per algorithm x
    scenario x parameter point), time_to_goal.png (one point per run: its
    restricted mean time to goal, robots that never arrived counted at the
    horizon; a panel per parameter point), arrivals.png (the fraction of goal
    robots arrived against time, Kaplan-Meier, one line per algorithm) and
    wall_time_vs_robots.png, the paper's Figure 2, which needs runs of the
    line scenario with several numbers of robots.
    """
    from mimics.interfaces.cli.battery_args import battery_records
    from mimics.interfaces.plots import battery_plots
    from mimics.world.output_paths import check_outputs

    try:
        check_outputs({"--out": out}, {"the battery folder": battery_records(directory)})
        written, skipped = battery_plots(directory, out)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    for path in written:
        _say(f"wrote {path}")
    for reason in skipped:
        _say(f"skipped: {reason}")
