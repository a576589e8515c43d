"""Export of a replay as a video and/or a GIF, without a display.

Videos are written with imageio's bundled ffmpeg (imageio-ffmpeg; no system
ffmpeg needed), streamed frame by frame: H.264 for ``.mp4``/``.mkv``/``.mov``/
``.avi``, and a GIF whose palette is computed per frame (exact colours for
these flat drawings, without holding the clip in memory).
"""

from __future__ import annotations

import contextlib
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mimics.interfaces.replay.drawing import Replayer
from mimics.interfaces.replay.frames import VIDEO_SUFFIXES, frame_times, open_run, replay_data
from mimics.world.errors import MimicsError


@dataclass(frozen=True)
class ExportResult:
    """What :func:`export_replay` wrote."""

    frames: int
    width: int
    height: int
    paths: tuple[Path, ...]
    wall_time: float


def require_ffmpeg() -> None:
    """Make sure the bundled ffmpeg is installed (the ``video`` extra), else one clear error."""
    try:
        import imageio_ffmpeg  # noqa: F401  (its 160 MB are not installed by default)
    except ImportError:
        raise MimicsError("videos, GIFs and animations need ffmpeg: pip install "
                          "'mimics-sim[video]' (or -e '.[video]' in a clone)") from None


def _check_output(path: Path, kind: str) -> Path:
    """Make sure ``path`` can be written (creating its folder), else one clear error."""
    require_ffmpeg()
    suffix = path.suffix.lower()
    if kind == "video" and suffix not in VIDEO_SUFFIXES:
        raise MimicsError(f"--video {path}: expected a file ending in "
                          f"{', '.join(VIDEO_SUFFIXES)}")
    if kind == "gif" and suffix != ".gif":
        raise MimicsError(f"--gif {path}: expected a file ending in .gif")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(path, "wb"):
            pass
    except OSError as exc:
        raise MimicsError(f"cannot write {path}: {exc.strerror or exc}") from None
    return path


class _Sink:
    """A stream of RGB frames into one file through imageio's ffmpeg."""

    def __init__(self, path: Path, size: tuple[int, int], fps: float) -> None:
        self.path = path
        if path.suffix.lower() == ".gif":
            import imageio_ffmpeg

            self._gen: Any = imageio_ffmpeg.write_frames(
                str(path), size, fps=fps, codec="gif", pix_fmt_out="pal8", macro_block_size=1,
                ffmpeg_log_level="error",
                output_params=["-vf", "split[a][b];[a]palettegen=stats_mode=single[p];"
                                      "[b][p]paletteuse=new=1:dither=none"])
            self._gen.send(None)
            self._writer = None
        else:
            import imageio.v2 as imageio

            self._writer = imageio.get_writer(str(path), format="FFMPEG", fps=fps,
                                              codec="libx264", quality=8, macro_block_size=16,
                                              pixelformat="yuv420p", ffmpeg_log_level="error")

    def append(self, frame: np.ndarray) -> None:
        if self._writer is not None:
            self._writer.append_data(frame)
        else:
            self._gen.send(np.ascontiguousarray(frame))

    def close(self) -> None:
        if self._writer is not None:
            self._writer.close()
        else:
            self._gen.close()


def export_replay(run: str | Path | Any, *, video: str | Path | None = None,
                  gif: str | Path | None = None, fps: float = 10.0, speed: float = 1.0,
                  robot_beams: int | None = None, trail: float = 5.0, width_px: int = 800,
                  progress: bool = True,
                  on_frame: Callable[[int, int], None] | None = None) -> ExportResult:
    """Write a run's replay as a video and/or a GIF, without a display.

    Args:
        run: a run folder, or a loaded run.
        video: output ``.mp4`` (or ``.mkv``, ``.mov``, ``.avi``) path.
        gif: output ``.gif`` path.
        fps: frames per second of the output.
        speed: simulated seconds per second of output; frames are ``speed / fps``
            simulated seconds apart.
        robot_beams: robot whose laser beams are recomputed and drawn.
        trail: seconds of trail behind each robot.
        width_px: pixels of the longer side of the map.
        progress: show a Rich progress bar on stderr.
        on_frame: called with (frames written, frames in all) after each frame
            (the workbench's progress bar).

    Raises:
        MimicsError: not a run, an unreadable trajectory, a bad argument or an
            unwritable output.

    Example:
        >>> export_replay("runs/cave-deployment-s0", video="cave.mp4", speed=4)  # doctest: +SKIP
    """
    if video is None and gif is None:
        raise MimicsError("replay export: give a --video and/or a --gif path")
    if not fps > 0 or not speed > 0 or width_px < 64:
        raise MimicsError(f"replay export: fps and speed must be positive and width >= 64 "
                          f"(got fps={fps}, speed={speed}, width={width_px})")
    outputs = [_check_output(Path(p), kind) for p, kind in ((video, "video"), (gif, "gif"))
               if p is not None]
    start = wallclock.perf_counter()
    try:
        count, (width, height) = _export_frames(run, outputs, fps, speed, robot_beams, trail,
                                                width_px, progress, on_frame)
    except BaseException:
        for path in outputs:  # no half-written or empty file is left behind
            path.unlink(missing_ok=True)
        raise
    return ExportResult(count, width, height, tuple(outputs),
                        wallclock.perf_counter() - start)


def _export_frames(run: str | Path | Any, outputs: list[Path], fps: float, speed: float,
                   robot_beams: int | None, trail: float, width_px: int, progress: bool,
                   on_frame: Callable[[int, int], None] | None = None
                   ) -> tuple[int, tuple[int, int]]:
    """Draw every frame of the replay into the sinks; returns the count and the size."""
    data = replay_data(open_run(run))
    replayer = Replayer.create(data, width_px=width_px, trail=trail, robot_beams=robot_beams)
    width, height = replayer.renderer.figure.canvas.get_width_height()
    times = frame_times(data.duration, fps, speed)
    sinks: list[_Sink] = []
    try:
        sinks = [_Sink(path, (width, height), fps) for path in outputs]
        with _progress(progress) as bar:
            task = bar.add_task(f"replay -> {', '.join(p.name for p in outputs)}",
                                total=len(times))
            for done, t in enumerate(times, start=1):
                replayer.show_at(float(t))
                frame = replayer.renderer.to_rgb()
                for sink in sinks:
                    sink.append(frame)
                bar.advance(task)
                if on_frame is not None:
                    on_frame(done, len(times))
    except (OSError, RuntimeError) as exc:
        raise MimicsError(f"writing {', '.join(map(str, outputs))} failed: {exc}") from None
    finally:
        for sink in sinks:
            with contextlib.suppress(OSError, RuntimeError):
                sink.close()
    return len(times), (width, height)


def _progress(enabled: bool) -> Any:
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TimeRemainingColumn

    return Progress("[progress.description]{task.description}", BarColumn(),
                    MofNCompleteColumn(), TimeRemainingColumn(),
                    console=Console(stderr=True), disable=not enabled, transient=False)
