"""A run's replay as an H.264 video that plays inline in a notebook cell.

The frames are those of ``mimics replay --video``: the replay's own
:class:`~mimics.interfaces.replay.Replayer` draws each one, at the times of
:func:`~mimics.interfaces.replay.frame_times`, and imageio's bundled ffmpeg
encodes them (H.264 as the export, with x264's ``veryfast`` preset: a third of
the default's time for the same size on these flat drawings) into a temporary
``.mp4``, read back and deleted; the bytes go into a ``<video>`` element. To
stay small it is thinned: without a ``speed``, the replay is sped up (2x, 4x,
5x, 10x...) so that it has at most ``max_frames`` frames; a video still over
``max_mb`` is made again at twice the speed (a 60 s Cave run at 640 pixels is
about 1 MB).

>>> choose_speed(duration=20.0, fps=10, speed=None, max_frames=201)
1.0
>>> choose_speed(duration=600.0, fps=10, speed=None, max_frames=201)
50.0
"""

from __future__ import annotations

import base64
import html
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mimics.world.errors import MimicsError
from mimics.world.limits import (
    MAX_IMAGE_SIDE,
    MAX_ROBOTS,
    MAX_TIME,
    check_number,
    check_whole,
)

#: Frames of an inline replay at most, unless a speed is given (20 s of video at 10 fps).
MAX_FRAMES = 201
#: Size of an inline replay at most (MB); a larger one is made again, faster.
MAX_MB = 8.0
_SPEEDS = (1.0, 2.0, 4.0, 5.0, 10.0, 20.0, 50.0, 100.0)


def choose_speed(duration: float, fps: float, speed: float | None, max_frames: int) -> float:
    """``speed``, or the first round speed that fits ``duration`` in ``max_frames`` frames."""
    if speed is not None:
        return float(speed)
    from mimics.interfaces.replay import frame_times  # Matplotlib: only when a replay is made

    for candidate in _SPEEDS:
        if len(frame_times(duration, fps, candidate)) <= max_frames:
            return candidate
    return duration * fps / max(max_frames - 2, 1)


@dataclass(frozen=True)
class Animation:
    """An inline replay: shown as a ``<video>`` by Jupyter (``_repr_html_``).

    Attributes:
        video: the H.264 ``.mp4`` bytes.
        frames: frames in the video.
        fps: frames per second of the video.
        speed: simulated seconds per second of video.
        width, height: pixels.
    """

    video: bytes
    frames: int
    fps: float
    speed: float
    width: int
    height: int

    @property
    def megabytes(self) -> float:
        """Size of the video (MB, 10^6 bytes)."""
        return len(self.video) / 1e6

    def save(self, path: str | Path) -> Path:
        """Write the video as an ``.mp4`` file."""
        out = Path(path)
        try:
            out.write_bytes(self.video)
        except OSError as exc:
            raise MimicsError(f"cannot write {out}: {exc.strerror or exc}") from None
        return out

    def _repr_html_(self) -> str:
        data = base64.b64encode(self.video).decode("ascii")
        label = html.escape(f"replay: {self.frames} frames at {self.fps:g} fps, "
                            f"{self.speed:g}x")
        return (f'<video class="mimics-replay" controls autoplay loop muted playsinline '
                f'width="{self.width}" data-frames="{self.frames}" data-fps="{self.fps:g}" '
                f'data-speed="{self.speed:g}" title="{label}">'
                f'<source type="video/mp4" src="data:video/mp4;base64,{data}"/></video>')

    def __repr__(self) -> str:
        return (f"Animation({self.frames} frames, {self.fps:g} fps, {self.speed:g}x, "
                f"{self.width}x{self.height}, {self.megabytes:.2f} MB)")


def check_drawing(*, width_px: Any, fps: Any, trail: Any, robot_beams: Any) -> None:
    """The drawing options of ``animate`` and ``mimics.show``, each within what a renderer
    can allocate and a run can hold (:mod:`mimics.world.limits`).

    Raises:
        MimicsError: one line naming the option and what was expected.
    """
    check_whole("width_px", width_px, 64, MAX_IMAGE_SIDE)
    check_number("fps", fps, 0.0, 1000.0, "a number of frames per second")
    check_number("trail", trail, 0.0, MAX_TIME, "a number of simulated seconds",
                 low_included=True)
    if robot_beams is not None:
        check_whole("robot_beams", robot_beams, 0, MAX_ROBOTS - 1)


def animate(run: Any, *, fps: float = 10.0, speed: float | None = None, width_px: int = 640,
            trail: float = 5.0, robot_beams: int | None = None, max_frames: int = MAX_FRAMES,
            max_mb: float = MAX_MB) -> Animation:
    """The replay of ``run`` as an inline video.

    Args:
        run: a loaded run (folder or memory) or a run folder.
        fps: frames per second of the video.
        speed: simulated seconds per second of video (None: 1, or faster so that
            the video has at most ``max_frames`` frames).
        width_px: pixels of the longer side of the map.
        trail: seconds of trail behind each robot.
        robot_beams: a robot whose laser beams are drawn (recomputed from the poses).
        max_frames: frames at most when ``speed`` is None.
        max_mb: a video larger than this is made again at twice the speed.

    Raises:
        MimicsError: a bad argument, or an unreadable run.
    """
    if isinstance(max_frames, bool) or not isinstance(max_frames, int) or max_frames < 2:
        raise MimicsError(f"max_frames: expected a whole number >= 2, got {max_frames!r}")
    check_drawing(width_px=width_px, fps=fps, trail=trail, robot_beams=robot_beams)
    check_number("animate: max_mb", max_mb, 0.0, 1e6, "a number of megabytes")
    if speed is not None:
        check_number("animate: speed", speed, 0.0, 1e15, "a number of simulated s per s")
    from mimics.interfaces.replay import Replayer, frame_times, open_run, replay_data

    data = replay_data(open_run(run))
    replayer = Replayer.create(data, width_px=width_px, trail=trail, robot_beams=robot_beams)
    width, height = replayer.renderer.figure.canvas.get_width_height()
    chosen = choose_speed(data.duration, fps, speed, max_frames)
    with tempfile.TemporaryDirectory(prefix="mimics-animate-") as scratch:
        path = Path(scratch) / "replay.mp4"
        for _ in range(8):  # each try doubles the speed: halves the frames
            times = frame_times(data.duration, fps, chosen)
            _encode(replayer, times, path, fps)
            video = path.read_bytes()
            if len(video) <= max_mb * 1e6 or len(times) <= 2:
                break
            chosen *= 2
    return Animation(video, len(times), float(fps), chosen, width, height)


def _encode(replayer: Any, times: Any, path: Path, fps: float) -> None:
    """Draw the frames at ``times`` and encode them into ``path`` (H.264, as the export)."""
    import imageio.v2 as imageio

    from mimics.interfaces.replay.export import require_ffmpeg

    require_ffmpeg()

    try:
        writer = imageio.get_writer(str(path), format="FFMPEG", fps=fps, codec="libx264",
                                    quality=8, macro_block_size=16, pixelformat="yuv420p",
                                    ffmpeg_log_level="error",
                                    output_params=["-preset", "veryfast"])
        try:
            for t in times:
                replayer.show_at(float(t))
                writer.append_data(replayer.renderer.to_rgb())
        finally:
            writer.close()
    except (OSError, RuntimeError) as exc:
        raise MimicsError(f"animate: encoding the video failed: {exc}") from None
