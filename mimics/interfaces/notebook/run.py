"""RunView: one run, in memory or in its folder, with its tables, plot and replay.

``mimics.simulate(...)`` returns one (recorded in memory: nothing is written
unless ``out=`` or :meth:`RunView.save` asks), and so does
``mimics.load_run(folder)``. In a notebook it shows its summary table and its
trajectories figure; ``.trajectory`` and ``.events`` are the DataFrames of
trajectory.parquet and events.parquet, ``.plot()`` the figure of ``mimics
plot``, ``.animate()`` the replay of ``mimics replay --video`` as an inline
video, ``.save(folder)`` a run folder every command reads.

Existing callers keep working: ``run.summary()`` (as ``RunResult.summary()``)
and ``run.summary["reached_goal"]`` (as a loaded run's dict) both give the
summary; ``run.status``, ``run.reached_goal`` and ``run.collisions`` come from
it; the other attributes of the engine's :class:`~mimics.engine.outcome.RunResult`
(``final_status``, ``goal_time``...; ``run.result`` is the whole of it) and of a
loaded :class:`~mimics.records.run_folder.Run` (``path``, ``scenario``,
``robot(i)``, ``read_trajectory``, ``scans``...) are reached through the view.

>>> import mimics
>>> run = mimics.simulate("line", "go_to_goal", robots=2, time=1.0, seed=1)
>>> run.status, run.summary()["robots"], run.summary["robots"], len(run.trajectory)
('time_limit', 2, 2, 22)
"""

from __future__ import annotations

import html
import shutil
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pandas as pd

from mimics.engine.outcome import RunResult
from mimics.interfaces.notebook.animation import MAX_FRAMES, MAX_MB, Animation, animate
from mimics.interfaces.notebook.html import (
    enable_figure_display,
    error_block,
    figure_img,
    rows_table,
)
from mimics.interfaces.user_errors import cell_places
from mimics.records.memory import MemoryRun, save_run
from mimics.records.recorder import RobotLogs, check_save_target, prepare_run_folder
from mimics.records.run_folder import Run
from mimics.records.run_folder import load_run as load_run_folder
from mimics.records.summary import summary_rows
from mimics.world.errors import MimicsError
from mimics.world.output_paths import as_path, check_outputs

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation
    from mimics.world.scenario import Scenario


class Summary(dict[str, Any]):
    """A run's summary (what summary.json holds): a dict that may also be called.

    ``run.summary()`` gives a copy, as ``RunResult.summary()`` did;
    ``run.summary["reached_goal"]`` reads it, as a loaded run's dict did.
    """

    def __call__(self) -> dict[str, Any]:
        return dict(self)


class RunView:
    """A finished run: its records, summary, figure and replay.

    Args:
        record: the run's records, in memory (``MemoryRun``) or in a folder
            (``Run``).
        result: the engine's outcome, when the run was simulated in this process.
    """

    def __init__(self, record: Run, result: RunResult | None = None) -> None:
        self.record = record
        self.result = result if result is not None else getattr(record, "result", None)

    # -- what a run is ---------------------------------------------------------------

    @property
    def path(self) -> Path | None:
        """The run folder, or None for a run in memory (not saved)."""
        return self.record.path

    @property
    def summary(self) -> Summary:
        """The summary (callable: ``run.summary()``; or a dict: ``run.summary["status"]``)."""
        return Summary(self.record.summary)

    @property
    def status(self) -> str:
        """How the run ended: completed, time_limit, wall_limit, stopped, error..."""
        return str(self.record.summary.get("status"))

    @property
    def reached_goal(self) -> int:
        """Robots that reached their goal."""
        return int(self.record.summary["reached_goal"])

    @property
    def collisions(self) -> int:
        """Robots deactivated by a collision."""
        return int(self.record.summary["collisions"])

    @property
    def scenario(self) -> Scenario:
        """The Scenario that was run (map, robot types, starts, goals, settings), the same
        after ``simulate()`` as after ``load_run()``; its name is ``run.scenario.name``."""
        return self.record.scenario

    @property
    def error(self) -> str:
        """What ended a run in error (the failure, its place and line); "" for other runs."""
        return str(self.record.summary.get("error") or "")

    @property
    def trajectory(self) -> pd.DataFrame:
        """One row per robot per recorded step (the columns of trajectory.parquet)."""
        return self.record.trajectory

    @property
    def events(self) -> pd.DataFrame:
        """Events and messages (the columns of events.parquet)."""
        return self.record.events

    def __getattr__(self, name: str) -> Any:
        # the engine's RunResult first (final_status, goal_time...), then the loaded run
        if name.startswith("__") or name in ("record", "result"):
            raise AttributeError(name)
        for owner in (self.result, self.record):
            if owner is not None and hasattr(owner, name):
                return getattr(owner, name)
        raise AttributeError(f"{type(self).__name__!r} has no attribute {name!r}"
                             + ("" if self.result is not None else
                                " (a loaded run has its summary, tables and scenario, not "
                                "the engine's arrays)"))

    def __repr__(self) -> str:
        s = self.record.summary
        where = "in memory" if self.path is None else str(self.path)
        return (f"RunView({s.get('scenario')} / {s.get('algorithm')} / seed {s.get('seed')}: "
                f"{s.get('robots')} robots, {s.get('status')}, {where})")

    # -- figures ---------------------------------------------------------------------

    def plot(self, *, width_px: int = 1000, height_px: int = 800) -> Any:
        """The trajectories figure of ``mimics plot`` (a Matplotlib Figure)."""
        from mimics.interfaces.plots import plot_run
        from mimics.world.limits import MAX_IMAGE_SIDE, check_whole

        check_whole("plot: width_px", width_px, 1, MAX_IMAGE_SIDE)
        check_whole("plot: height_px", height_px, 1, MAX_IMAGE_SIDE)
        enable_figure_display()
        return plot_run(self.record, None, width_px=width_px, height_px=height_px)

    def animate(self, *, fps: float = 10.0, speed: float | None = None, width_px: int = 640,
                trail: float = 5.0, robot_beams: int | None = None,
                max_frames: int = MAX_FRAMES, max_mb: float = MAX_MB) -> Animation:
        """The replay as a video that plays in the cell (the frames of ``mimics replay``).

        Args:
            fps: frames per second of the video.
            speed: simulated seconds per second of video (None: 1, or faster so
                that the video has at most ``max_frames`` frames).
            width_px: pixels of the longer side of the map.
            trail: seconds of trail behind each robot.
            robot_beams: a robot whose laser beams are drawn.
            max_frames: frames at most when ``speed`` is None.
            max_mb: a larger video is made again at twice the speed.
        """
        return animate(self.record, fps=fps, speed=speed, width_px=width_px, trail=trail,
                       robot_beams=robot_beams, max_frames=max_frames, max_mb=max_mb)

    # -- files ---------------------------------------------------------------------

    def save(self, folder: str | Path, *, robot_logs: RobotLogs = "auto") -> Path:
        """Write the run folder (``mimics report``, ``replay``, ``plot`` and ``load_run``
        read it); a loaded run's folder is copied.

        Args:
            folder: a new or empty folder, or an earlier run's (its records are replaced);
                not the run's own folder nor a folder holding other files.
            robot_logs: per-robot logs for a run in memory: ``"auto"`` (up to 200
                robots), ``"on"`` or ``"off"``.

        Raises:
            MimicsError: a folder holding other files, the run's own folder (or one in
                it, or around it), or one that cannot be written; nothing is written.
        """
        out = as_path("save: folder", folder)
        check_save_target(out)
        if isinstance(self.record, MemoryRun):
            return save_run(self.record, out, robot_logs=robot_logs)
        source = Path(self.record.path)
        # a copy into the run's own folder, into one of its records or around it would
        # delete what it copies
        check_outputs({"save: folder": out}, {"the run's own folder": source})
        prepare_run_folder(out)
        try:
            shutil.copytree(source, out, dirs_exist_ok=True)
        except (OSError, shutil.Error) as exc:
            raise MimicsError(f"{out}: cannot copy the run folder here ({exc})") from None
        return out

    # -- in a notebook -----------------------------------------------------------------

    def _repr_html_(self) -> str:
        summary = self.record.summary
        title = (f"{summary.get('scenario')} / {summary.get('algorithm')} / seed "
                 f"{summary.get('seed')}")
        parts = [f"<div class=\"mimics-run\"><h4>{_escape(title)}</h4>"]
        if self.error:  # what went wrong first, where the eye lands
            parts.append(error_block(cell_places(self.error)))
        parts.append(rows_table(summary_rows(summary)))
        try:
            figure = self.plot(width_px=800, height_px=600)
        except MimicsError as exc:  # an empty trajectory: the table alone
            parts.append(f"<p>{_escape(str(exc))}</p>")
        else:
            parts.append(figure_img(figure, "trajectories"))
        parts.append("</div>")
        return "".join(parts)


def _escape(text: str) -> str:
    return html.escape(text)


def record_run(sim: Simulation, out: str | Path | None = None, *,
               record_scans: bool = False) -> RunView:
    """Run a prepared simulation, recorded in memory (``out`` None) or in its run folder.

    Raises:
        MimicsError: ``record_scans`` without ``out``, or a run too big to keep in memory.
    """
    from mimics.records.memory import MemoryRecorder
    from mimics.records.runner import run_to_folder

    if out is None:
        if record_scans:
            raise MimicsError("record_scans: give out=FOLDER too (the scans go in the run folder)")
        check_memory_recording(sim)
        recorder = MemoryRecorder()
        sim.observers.append(recorder)
        result = sim.run()
        sim.observers.remove(recorder)
        return RunView(MemoryRun(recorder, result), result)
    result = run_to_folder(sim, out, record_scans=record_scans)
    return RunView(load_run_folder(out), result)


def check_memory_recording(sim: Simulation) -> None:
    """Refuse a run whose records would not fit in memory (every row is kept until the end).

    Raises:
        MimicsError: one line with the figures, suggesting ``out=FOLDER``.
    """
    from mimics.records import resources

    whole = 2**62  # the rows are never flushed: the buffer is the whole run
    estimate = resources.run_memory(sim.scenario, flush_rows=whole, time=sim.time_limit)
    available = resources.available_memory()
    if available is not None and estimate.total > available:
        raise MimicsError(
            f"scenario {sim.scenario.name!r}: recording this run in memory needs about "
            f"{resources.size_text(estimate.total)}, more than the "
            f"{resources.size_text(available)} available: give out=FOLDER (the run is then "
            "written as it goes) or a shorter time")
