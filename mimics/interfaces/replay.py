"""Replay of a finished run from its folder: a Matplotlib window, or a video/GIF.

The run's ``trajectory.parquet`` (one row per robot per recorded step) is
turned into dense arrays over (recorded step, robot); a robot missing from
later rows keeps its last pose and state. A frame at simulated time ``t``
shows the last recorded step at or before ``t``, exactly as logged (no
interpolation). Frames are ``speed / fps`` simulated seconds apart, from 0 to
the end of the run (the final state is always the last frame).

Laser beams are not logged, so a replay recomputes them for the chosen robot
at each frame with the engine's ray kernel (``mimics.engine.ranging.ranger.cast_rays``)
against the walls and the other robots at their logged poses. Those beams are
noise-free (the ranger noise of the run is not logged). If the kernel cannot be
imported, beams are skipped with a one-line notice.

Videos are written with imageio's bundled ffmpeg (imageio-ffmpeg; no system
ffmpeg needed), streamed frame by frame: H.264 for ``.mp4``/``.mkv``/``.mov``/
``.avi``, and a GIF whose palette is computed per frame (exact colours for
these flat drawings, without holding the clip in memory).

>>> from mimics.interfaces.replay import frame_times
>>> frame_times(duration=1.0, fps=10, speed=4).tolist()
[0.0, 0.4, 0.8, 1.0]
"""

from __future__ import annotations

import contextlib
import math
import sys
import time as wallclock
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numba
import numpy as np

from mimics.engine.state import Status
from mimics.interfaces.render import WorldRenderer, beam_segments
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario

VIDEO_SUFFIXES = (".mp4", ".mkv", ".mov", ".avi")
_EPS = 1e-9
_TRAJECTORY_COLUMNS = ("time", "step", "robot", "x", "y", "theta", "status")
_STOP_KINDS = {"reached_goal": Status.REACHED_GOAL, "collision": Status.COLLIDED,
               "escaped": Status.ESCAPED, "exception": Status.ERROR}


MAX_FRAMES = 1_000_000  # frames of one replay (a day of video at 10 fps)


def frame_times(duration: float, fps: float, speed: float) -> np.ndarray:
    """Simulated times of the frames: every ``speed / fps`` s from 0, plus the end."""
    if not fps > 0 or not speed > 0:
        raise MimicsError(f"replay: fps and speed must be positive, got fps={fps}, "
                          f"speed={speed}")
    step = speed / fps
    frames = duration / step
    if not frames <= MAX_FRAMES:  # also NaN and inf
        raise MimicsError(f"replay: {duration:g} s at {speed:g} simulated s per s and {fps:g} "
                          f"fps is {frames:.3g} frames, over the limit of {MAX_FRAMES} (expected "
                          "a higher speed or fewer fps)")
    count = math.floor(frames + _EPS) + 1
    times = np.arange(count) * step
    if duration - times[-1] > _EPS:
        times = np.append(times, duration)
    return np.round(times, 9)


def open_run(run: str | Path | Any) -> Any:
    """A loaded run: a folder path goes through ``mimics.load_run``; objects pass through.

    Raises:
        MimicsError: when the folder is not a run or its files are unreadable.
    """
    if not isinstance(run, str | Path):
        return run
    path = Path(run)
    if not path.is_dir():
        raise MimicsError(f"{path}: not a run folder (no such directory)")
    from mimics.records.run_folder import load_run

    return load_run(path)


@dataclass
class ReplayData:
    """A run's trajectory as dense arrays, ready to draw at any time.

    Attributes:
        times: ``(T,)`` simulated times of the recorded steps, increasing.
        pose: ``(T, n, 3)`` true x, y, theta (float32).
        status: ``(T, n)`` ``Status`` codes.
        livelock: ``(T, n)`` active robots in a livelock (from the events).
        scenario: the run's scenario (map, robot types, goals).
        title: scenario / algorithm / seed.
    """

    times: np.ndarray
    pose: np.ndarray
    status: np.ndarray
    livelock: np.ndarray
    scenario: Scenario
    title: str

    @property
    def n(self) -> int:
        """Number of robots."""
        return int(self.pose.shape[1])

    @property
    def duration(self) -> float:
        """Simulated time of the last recorded step (s)."""
        return float(self.times[-1])

    @property
    def half_sizes(self) -> tuple[np.ndarray, np.ndarray]:
        """Half length and half width of every robot."""
        s = self.scenario
        lengths = np.array([t.length for t in s.types])[s.type_index]
        widths = np.array([t.width for t in s.types])[s.type_index]
        return lengths / 2, widths / 2

    def index_at(self, t: float) -> int:
        """Index of the last recorded step at or before ``t`` (clamped to the run)."""
        k = int(np.searchsorted(self.times, t + _EPS, side="right")) - 1
        return min(max(k, 0), len(self.times) - 1)

    def trails(self, k: int, seconds: float, points: int) -> np.ndarray | None:
        """Recent positions ``(n, m, 2)`` up to step ``k`` over ``seconds``, at most
        ``points`` + 1 of them per robot."""
        if seconds <= 0:
            return None
        first = int(np.searchsorted(self.times, self.times[k] - seconds - _EPS))
        if k - first < 1:
            return None
        idx = np.unique(np.linspace(first, k, min(points + 1, k - first + 1)).round().astype(int))
        return self.pose[idx, :, :2].transpose(1, 0, 2)


def replay_data(run: Any) -> ReplayData:
    """Dense arrays from a loaded run (``summary``, ``trajectory``, ``events``, ``scenario``).

    Raises:
        MimicsError: when the trajectory lacks columns or names unknown robots.
    """
    scenario: Scenario = run.scenario
    n = scenario.robot_count
    reader = getattr(run, "read_trajectory", None)  # a Run reads only the columns needed
    try:
        traj = (reader(columns=list(_TRAJECTORY_COLUMNS)) if callable(reader)
                else run.trajectory)
    except MimicsError:
        raise
    except Exception as exc:  # a truncated or corrupt file, whatever the reader raised
        raise MimicsError(f"the run's trajectory cannot be read: {exc}") from exc
    missing = [c for c in _TRAJECTORY_COLUMNS if c not in traj.columns]
    if missing:
        raise MimicsError(f"the run's trajectory lacks the column(s) {', '.join(missing)}")
    if len(traj) == 0:
        raise MimicsError("the run's trajectory is empty: nothing to replay")
    steps = traj["step"].to_numpy(np.int64)
    robot = traj["robot"].to_numpy(np.int64)
    if robot.min() < 0 or robot.max() >= n:
        raise MimicsError(f"the run's trajectory names robot {int(robot.max())}, but its "
                          f"scenario has robots 0..{n - 1}")
    recorded, row_step = np.unique(steps, return_inverse=True)
    times = np.zeros(len(recorded))
    times[row_step] = traj["time"].to_numpy(np.float64)
    xyz = traj[["x", "y", "theta"]].to_numpy(np.float32)
    # Row 0 is the scenario's initial state, used until a robot's first record.
    steps_n = len(recorded) + 1
    pose = np.empty((steps_n, n, 3), dtype=np.float32)
    pose[0] = scenario.stages[:, :3]
    status = np.zeros((steps_n, n), dtype=np.int8)
    have = np.zeros((steps_n, n), dtype=bool)
    have[0] = True
    pose[row_step + 1, robot] = xyz
    status[row_step + 1, robot] = traj["status"].to_numpy(np.int8)
    have[row_step + 1, robot] = True
    source = np.where(have, np.arange(steps_n)[:, None], 0)
    np.maximum.accumulate(source, axis=0, out=source)
    cols = np.arange(n)[None, :]
    pose, status = pose[source, cols][1:], status[source, cols][1:]
    last_row = source[-1]
    _apply_stops(status, times, last_row - 1, _events(run))
    livelock = _livelock_mask(times, n, _events(run))
    summary = getattr(run, "summary", {}) or {}
    title = " / ".join(str(summary[k]) for k in ("scenario", "algorithm") if k in summary)
    if "seed" in summary:
        title += f" / seed {summary['seed']}"
    return ReplayData(times, pose, status, livelock, scenario, title or scenario.name)


def _events(run: Any) -> Any:
    events = getattr(run, "events", None)
    if events is None or len(events) == 0 or "kind" not in events.columns:
        return None
    return events


def _apply_stops(status: np.ndarray, times: np.ndarray, last: np.ndarray, events: Any) -> None:
    """A robot whose rows stop while it looked active takes the state its events give."""
    if events is None:
        return
    stops = events[events["kind"].isin(list(_STOP_KINDS))]
    for t, r, kind in zip(stops["time"], stops["robot"], stops["kind"], strict=True):
        r = int(r)
        if not 0 <= r < status.shape[1]:
            continue
        after = max(int(last[r]) + 1, int(np.searchsorted(times, float(t) - _EPS)))
        tail = status[after:, r]
        tail[tail == Status.ACTIVE] = _STOP_KINDS[kind]


def _livelock_mask(times: np.ndarray, n: int, events: Any) -> np.ndarray:
    """Per recorded step, the robots between a ``livelock`` event and its end."""
    mask = np.zeros((len(times), n), dtype=bool)
    if events is None:
        return mask
    rows = events[events["kind"].isin(["livelock", "livelock_end"])].sort_values("time")
    open_since: dict[int, float] = {}
    for t, r, kind in zip(rows["time"], rows["robot"], rows["kind"], strict=True):
        r = int(r)
        if not 0 <= r < n:
            continue
        if kind == "livelock":
            open_since[r] = float(t)
        elif r in open_since:
            start = open_since.pop(r)
            mask[(times >= start - _EPS) & (times < float(t) - _EPS), r] = True
    for r, start in open_since.items():
        mask[times >= start - _EPS, r] = True
    return mask


class BeamCaster:
    """Recomputes one robot's laser beams from logged poses with the engine's ray kernel.

    Args:
        scenario: the run's scenario (walls and robot types).
    """

    def __init__(self, scenario: Scenario) -> None:
        from mimics.engine.ranging.ranger import RangerQuery, cast_rays
        from mimics.engine.ranging.wall_index import build_wall_index
        from mimics.engine.robot_index import build_robot_index, index_cell
        from mimics.engine.state import TypeArrays

        self._query, self._cast, self._robot_index = RangerQuery, cast_rays, build_robot_index
        self.scenario = scenario
        self.types = TypeArrays.from_scenario(scenario)
        types = self.types
        self.walls = build_wall_index(scenario.map.segments, scenario.map.bounds,
                                      float(np.max(types.max_range, initial=0.0)))
        self.robot_cell = index_cell(types.max_range, types.half_length, types.half_width)

    @classmethod
    def available(cls, scenario: Scenario) -> BeamCaster | None:
        """A caster, or None (after a one-line notice) when the kernel cannot be imported."""
        try:
            return cls(scenario)
        except ImportError as exc:
            print(f"mimics: beams skipped: the engine's ray kernel is unavailable ({exc})",
                  file=sys.stderr)
            return None

    def beams(self, robot: int, pose: np.ndarray, status: np.ndarray) -> np.ndarray | None:
        """Beam segments ``(b, 2, 2)`` of ``robot`` in the world ``pose``/``status``
        (None when the robot is inactive or has no ranger)."""
        types = self.types
        if status[robot] != Status.ACTIVE or types.beam_count[robot] == 0:
            return None
        pose = np.ascontiguousarray(pose, dtype=np.float64)
        if self.scenario.settings.inactive_as_obstacles:
            solid = status != Status.ESCAPED
        else:
            solid = status == Status.ACTIVE
        robots = self._robot_index(np.ascontiguousarray(pose[:, :2]),
                                   np.ascontiguousarray(pose[:, 2]), types.half_length,
                                   types.half_width, solid, cell=self.robot_cell)
        ids = np.array([robot], dtype=np.int64)
        query = self._query(origins=np.ascontiguousarray(pose[ids, :2]),
                            headings=np.ascontiguousarray(pose[ids, 2]),
                            offsets=np.ascontiguousarray(types.beam_offsets[ids]),
                            max_range=types.max_range[ids], robot=ids)
        threads = numba.get_num_threads()
        numba.set_num_threads(1)  # one scan: a thread pool only adds launch latency
        try:
            ranges, _ = self._cast(query, self.walls, robots)
        finally:
            numba.set_num_threads(threads)
        return beam_segments(pose[robot, :2], pose[robot, 2], types.beam_offsets[robot],
                             np.asarray(ranges)[0])


class Replayer:
    """Draws a :class:`ReplayData` at any simulated time into a renderer.

    Args:
        data: the run's dense arrays.
        renderer: where to draw (see :meth:`create`).
        trail: seconds of trail behind each robot.
        robot_beams: robot whose laser beams are recomputed and drawn, or None.
    """

    def __init__(self, data: ReplayData, renderer: WorldRenderer, *, trail: float = 5.0,
                 robot_beams: int | None = None) -> None:
        if robot_beams is not None and not 0 <= robot_beams < data.n:
            raise MimicsError(f"replay: robot {robot_beams} for beams is not in 0..{data.n - 1}")
        self.data = data
        self.renderer = renderer
        self.trail = trail
        self.trail_points = 16 if data.n <= 300 else 6
        self.robot_beams = robot_beams
        self.caster = None if robot_beams is None else BeamCaster.available(data.scenario)

    @classmethod
    def create(cls, data: ReplayData, *, width_px: int = 800, extra_bottom_px: int = 0,
               figure: Any = None, **options: Any) -> Replayer:
        """A replayer drawing into a new renderer (off-screen unless ``figure`` is given)."""
        hl, hw = data.half_sizes
        m = data.scenario.map
        renderer = WorldRenderer.create(m.segments, m.bounds, hl, hw, data.scenario.goals,
                                        width_px=width_px, extra_bottom_px=extra_bottom_px,
                                        figure=figure, title=data.title)
        return cls(data, renderer, **options)

    def show_at(self, t: float) -> int:
        """Set the renderer to the state at simulated time ``t``; returns the step index."""
        data = self.data
        k = data.index_at(t)
        beams = None
        if self.caster is not None and self.robot_beams is not None:
            beams = self.caster.beams(self.robot_beams, data.pose[k], data.status[k])
        self.renderer.update(data.pose[k], data.status[k], max(float(t), 0.0) if
                             t <= data.duration else data.duration,
                             livelock=data.livelock[k],
                             trails=data.trails(k, self.trail, self.trail_points), beams=beams)
        return k


@dataclass(frozen=True)
class ExportResult:
    """What :func:`export_replay` wrote."""

    frames: int
    width: int
    height: int
    paths: tuple[Path, ...]
    wall_time: float


def _check_output(path: Path, kind: str) -> Path:
    """Make sure ``path`` can be written (creating its folder), else one clear error."""
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


class ReplayWindow:
    """An interactive replay: play/pause, a time slider and a speed slider.

    Keys: space plays or pauses, left/right step one frame back or forward.

    Args:
        data: the run's dense arrays.
        fps: frames per second while playing.
        speed: initial simulated seconds per second (1/4 to 64, powers of 2).
        robot_beams: robot whose beams are drawn, or None.
        trail: seconds of trail behind each robot.
        figure: a figure to draw into (default: a new pyplot window).
    """

    _CONTROLS_PX = 64

    def __init__(self, data: ReplayData, *, fps: float = 10.0, speed: float = 1.0,
                 robot_beams: int | None = None, trail: float = 5.0,
                 figure: Any = None) -> None:
        from matplotlib.widgets import Button, Slider

        if figure is None:
            import matplotlib.pyplot as plt

            figure = plt.figure(num=f"mimics replay: {data.title}")
        self.data = data
        self.fps = fps
        self.replayer = Replayer.create(data, extra_bottom_px=self._CONTROLS_PX, figure=figure,
                                        trail=trail, robot_beams=robot_beams)
        self.figure = figure
        self.time = 0.0
        self.playing = False
        height = figure.bbox.height
        row = 10 / height
        tall = 22 / height
        self._play_ax = figure.add_axes((0.01, row + tall + 6 / height, 0.1, tall))
        self.play_button = Button(self._play_ax, "Play")
        self.play_button.on_clicked(lambda _event: self.toggle())
        self.time_slider = Slider(figure.add_axes((0.2, row + tall + 6 / height, 0.68, tall)),
                                  "time (s)", 0.0, max(data.duration, 1e-9), valinit=0.0)
        self.time_slider.on_changed(self._on_time)
        exponent = float(np.clip(np.round(np.log2(speed)), -2, 6))
        self.speed_slider = Slider(figure.add_axes((0.2, row, 0.3, tall)), "speed", -2.0, 6.0,
                                   valinit=exponent, valstep=1.0)
        self.speed_slider.valtext.set_text(f"x{2 ** exponent:g}")
        self.speed_slider.on_changed(
            lambda value: self.speed_slider.valtext.set_text(f"x{2 ** value:g}"))
        self.timer = figure.canvas.new_timer(interval=max(1, int(1000 / fps)))
        self.timer.add_callback(self.tick)
        figure.canvas.mpl_connect("key_press_event", self._on_key)
        self.replayer.show_at(0.0)

    @property
    def speed(self) -> float:
        """Simulated seconds per second of playback."""
        return float(2.0 ** self.speed_slider.val)

    def seek(self, t: float) -> None:
        """Show simulated time ``t`` (clamped to the run) and move the slider there."""
        self.time = float(np.clip(t, 0.0, self.data.duration))
        self.time_slider.set_val(self.time)  # calls _on_time, which draws

    def _on_time(self, value: float) -> None:
        self.time = float(value)
        self.replayer.show_at(self.time)
        self.figure.canvas.draw_idle()

    def toggle(self) -> None:
        """Play or pause (playing from the end starts again at 0)."""
        self.playing = not self.playing
        self.play_button.label.set_text("Pause" if self.playing else "Play")
        if self.playing:
            if self.time >= self.data.duration - _EPS:
                self.seek(0.0)
            self.timer.start()
        else:
            self.timer.stop()
        self.figure.canvas.draw_idle()

    def tick(self) -> None:
        """Advance one frame while playing; pause at the end."""
        if not self.playing:
            return
        self.seek(self.time + self.speed / self.fps)
        if self.time >= self.data.duration - _EPS:
            self.toggle()

    def _on_key(self, event: Any) -> None:
        if event.key == " ":
            self.toggle()
        elif event.key in ("left", "right"):
            step = self.speed / self.fps
            self.seek(self.time + (step if event.key == "right" else -step))

    def show(self) -> None:
        """Open the window and block until it is closed."""
        import matplotlib.pyplot as plt

        plt.show()
