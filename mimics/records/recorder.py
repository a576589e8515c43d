"""RunRecorder: the observer that writes a run folder while the simulation runs.

On start it writes scenario.toml (what is run, with the ``[run]`` table) and
the initial rows; after each step it buffers the rows of the robots active at
the start of the step (:mod:`mimics.records.trajectory`) and the new events and
messages (:mod:`mimics.records.events`), writing a part file every
``flush_rows`` rows or ``flush_seconds`` of wall time. At the end it merges
the parts into trajectory.parquet and events.parquet, writes the per-robot
logs from them (``robot_logs``: ``"auto"`` up to :data:`AUTO_ROBOT_LOGS`
robots, ``"on"``, ``"off"``), summary.txt, and summary.json last. With
``record_scans`` it also writes the laser scans (:mod:`mimics.records.scans`). A run that
fits in one part (most) still has its tables in memory at the end: the logs
are then made from those while another thread writes them as Parquet.

>>> import tempfile
>>> from mimics.engine.simulation import Simulation
>>> from mimics.scenarios.line import scenario
>>> from mimics.algorithms import go_to_goal
>>> folder = tempfile.mkdtemp()
>>> recorder = RunRecorder(folder)
>>> result = Simulation(scenario(robots=2), go_to_goal, seed=1, observers=[recorder]).run()
>>> sorted(p.name for p in recorder.folder.iterdir())  # doctest: +NORMALIZE_WHITESPACE
['events.parquet', 'robots', 'scenario.toml', 'summary.json', 'summary.txt',
 'trajectory.parquet']
"""

from __future__ import annotations

import importlib.metadata
import shutil
import time
import uuid
from concurrent.futures import ThreadPoolExecutor
from datetime import datetime
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
import pyarrow as pa

import mimics
from mimics.engine.outcome import RunResult
from mimics.records.arrow_columns import empty_table
from mimics.records.events import EVENTS_SCHEMA, EventBuffer
from mimics.records.layout import (
    EVENTS,
    EVENTS_PARTS,
    FLUSH_ROWS,
    RECORD_NAMES,
    SCANS,
    SCANS_PARTS,
    SCENARIO_TOML,
    SUMMARY_JSON,
    TRAJECTORY,
    TRAJECTORY_PARTS,
)
from mimics.records.parts import COMPRESSION, PartWriter
from mimics.records.robot_logs import write_robot_logs
from mimics.records.scans import ScanBuffer, ScanLayout
from mimics.records.scenario_record import write_scenario_record
from mimics.records.summary import write_summary
from mimics.records.trajectory import TRAJECTORY_SCHEMA, TrajectoryBuffer
from mimics.world.errors import MimicsError

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation
    from mimics.world.scenario import Scenario

RobotLogs = Literal["auto", "on", "off"]
ROBOT_LOG_CHOICES = ("auto", "on", "off")
AUTO_ROBOT_LOGS = 200  # "auto" writes per-robot logs up to this many robots
# a run of several parts makes its logs from the merged tables up to this many rows
# (about 200 MB); beyond, from the files read back a batch of robots at a time
KEEP_ROWS = 2_000_000


def mimics_version() -> str:
    """The running mimics version (from the package, else from its installed metadata)."""
    version = getattr(mimics, "__version__", None)
    if version is None:
        try:
            version = importlib.metadata.version("mimics-sim")  # the distribution's name
        except importlib.metadata.PackageNotFoundError:
            version = "unknown"
    return str(version)


def check_save_target(folder: Path) -> None:
    """Refuse to save a run into a folder holding anything but an earlier run's records
    (``RunView.save``, ``save_run``: a save never mixes a run with other files).

    Raises:
        MimicsError: naming the folder and the first other file; nothing is written.
    """
    if folder.exists() and not folder.is_dir():
        raise MimicsError(f"{folder}: a file (expected a new or empty folder, or an earlier "
                          "run's)")
    if not folder.is_dir():
        return
    try:
        others = sorted(entry.name for entry in folder.iterdir()
                        if entry.name not in RECORD_NAMES)
    except OSError as exc:
        raise MimicsError(f"{folder}: cannot read the folder ({exc.strerror or exc})") from None
    if others:
        raise MimicsError(f"{folder}: not empty, it holds {others[0]} (expected a new or empty "
                          "folder, or an earlier run's)")


def prepare_run_folder(folder: Path) -> None:
    """Make ``folder``, removing the records of an earlier run in it (summary.json first).

    Raises:
        MimicsError: when it holds records but is not a run folder (nothing is
            removed then), or cannot be written.
    """
    try:
        folder.mkdir(parents=True, exist_ok=True)
        present = [name for name in RECORD_NAMES if (folder / name).exists()]
        if present and not (folder / SCENARIO_TOML).is_file():
            # not a run folder (every run writes scenario.toml first): the user's files
            raise MimicsError(f"{folder}: holds {present[0]} but is not a run folder "
                              f"(no {SCENARIO_TOML}); nothing was removed: give a new or "
                              "empty folder, or an earlier run's folder")
        for name in RECORD_NAMES:  # summary.json first: an old one must not mark this run
            path = folder / name
            if path.is_dir():
                shutil.rmtree(path)
            elif path.exists():
                path.unlink()
    except OSError as exc:
        raise MimicsError(f"{folder}: cannot write the run folder here "
                          f"({exc.strerror or exc})") from None


class RunRecorder:
    """Records one simulation into ``folder`` (an observer: pass it in ``observers``).

    Args:
        folder: the run folder; created if needed. Files of an earlier run in
            it (the names in :data:`mimics.records.layout.RECORD_NAMES`) are
            removed when the run starts, summary.json first.
        robot_logs: ``"auto"`` (up to 200 robots), ``"on"`` or ``"off"``.
        every: record every ``every``-th step in full (1: all steps); steps
            where robots are deactivated and the last step are always recorded
            for those robots.
        flush_rows: write a part once this many trajectory rows are buffered.
        flush_seconds: write a part at least this often (wall-clock seconds),
            so that a killed run loses little.
        compression: Parquet codec (``"zstd"``, ``"snappy"``, ``"none"``...).
        record_scans: also record the laser scans (scans.parquet), at the
            steps recorded in full.
        extra: keys added to summary.json.

    Raises:
        MimicsError: on a bad option.
    """

    def __init__(self, folder: str | Path, *, robot_logs: RobotLogs = "auto", every: int = 1,
                 flush_rows: int = FLUSH_ROWS, flush_seconds: float = 10.0,
                 compression: str = COMPRESSION, record_scans: bool = False,
                 extra: dict[str, Any] | None = None) -> None:
        if robot_logs not in ROBOT_LOG_CHOICES:
            raise MimicsError(f"robot_logs: expected auto, on or off, got {robot_logs!r}")
        if isinstance(every, bool) or not isinstance(every, int) or every < 1:
            raise MimicsError(f"every: expected a whole number >= 1, got {every!r}")
        if isinstance(flush_rows, bool) or not isinstance(flush_rows, int) or flush_rows < 1:
            raise MimicsError(f"flush_rows: expected a whole number >= 1, got {flush_rows!r}")
        if not flush_seconds > 0:
            raise MimicsError(f"flush_seconds: expected a positive number, got {flush_seconds!r}")
        self.folder = Path(folder)
        self.robot_logs = robot_logs
        self.every = every
        self.flush_rows = flush_rows
        self.flush_seconds = float(flush_seconds)
        self.record_scans = bool(record_scans)
        self.compression = compression
        self.extra = dict(extra or {})
        self.run_info: dict[str, Any] = {}
        self._recorded_edits: tuple[Any, ...] = ()  # the edits in scenario.toml as written
        self.summary_path: Path | None = None
        self._trajectory = TrajectoryBuffer(self._writer(TRAJECTORY_PARTS, TRAJECTORY_SCHEMA))
        self._events = EventBuffer(self._writer(EVENTS_PARTS, EVENTS_SCHEMA))
        self._scans: ScanBuffer | None = None  # made at the start, from the scenario
        self._scan_rows = 0
        self._was_active = np.zeros(0, dtype=bool)
        self._full_step = -1  # last step recorded for every robot active at its start
        self._last_flush = 0.0
        self._trajectory_rows = 0
        self._event_rows = 0
        self._step_time = 0.0  # wall seconds spent in on_start and on_step
        self._started = False
        self._closed = False

    # -- observer hooks ------------------------------------------------------

    def on_start(self, sim: Simulation) -> None:
        """Clear old records, write scenario.toml and the initial rows."""
        if self._started:
            raise MimicsError(f"{self.folder}: a RunRecorder records one run only")
        began = time.perf_counter()
        self._started = True
        self._open_folder()
        self.run_info = {
            "seed": sim.seed, "algorithm": sim.controller.name, "policy": sim.policy,
            "time_limit": sim.time_limit, "wall_limit": sim.wall_limit,
            "mimics_version": mimics_version(),
            "created": datetime.now().astimezone().isoformat(timespec="seconds"),
            "uuid": str(uuid.uuid4()),
        }
        self._write_scenario(sim.scenario)
        self._recorded_edits = sim.scenario.edits
        everyone = np.arange(sim.state.n)
        if self.record_scans:
            layout = ScanLayout.from_scenario(sim.scenario)
            self._scans = ScanBuffer(self._writer(SCANS_PARTS, layout.schema()), layout)
            self._scans.add(sim.state, np.flatnonzero(sim.state.active))
        self._trajectory.add(sim.state, everyone)
        self._events.collect(sim.events, sim.state, everyone)
        self._full_step = sim.state.step
        self._was_active = sim.state.active
        self._last_flush = time.perf_counter()
        self._step_time += self._last_flush - began

    def on_step(self, sim: Simulation) -> None:
        """Buffer this step's rows and events; write a part when the buffer is full."""
        if not self._started:
            raise MimicsError("RunRecorder: attached after the simulation had started")
        began = time.perf_counter()
        state = sim.state
        active = state.active
        started = self._was_active.nonzero()[0]  # = np.flatnonzero, minus its wrapper
        if state.step % self.every == 0:
            self._trajectory.add(state, started)
            if self._scans is not None:
                self._scans.add(state, np.flatnonzero(active))
            self._full_step = state.step
        else:
            self._trajectory.add(state, np.flatnonzero(self._was_active & ~active))
        self._events.collect(sim.events, state, started)
        self._was_active = active
        now = time.perf_counter()
        if self._trajectory.rows >= self.flush_rows or now - self._last_flush >= self.flush_seconds:
            self.flush()
            now = time.perf_counter()
        self._step_time += now - began

    def on_edit(self, sim: Simulation, applied: Any) -> None:
        """Take an edit's event now, with the step it was applied at."""
        self._events.collect(sim.events, sim.state, np.zeros(0, dtype=np.int64))

    def on_end(self, sim: Simulation, result: RunResult) -> None:
        """Merge the parts, write the robot logs, summary.txt and summary.json (last)."""
        if self._closed:
            return
        began = time.perf_counter()
        if sim.scenario.edits != self._recorded_edits:  # edits made during the run
            self._write_scenario(sim.scenario)
        self._add_last_step(sim)
        logs = self.robot_logs == "on" or (self.robot_logs == "auto"
                                           and sim.state.n <= AUTO_ROBOT_LOGS)
        if logs and self._trajectory.writer.parts == 0 and self._events.writer.parts == 0:
            self._close_with_logs(sim.scenario)
        else:
            # the logs of a run of several parts are made from the tables read to merge
            # them, when those fit in memory, rather than from the merged files read back
            keep = logs and self._trajectory.writer.rows + self._trajectory.rows <= KEEP_ROWS
            self.close(keep=keep)
            if logs:  # a table not kept (a lone part, renamed) is read back
                write_robot_logs(self.folder, sim.scenario, self.run_info,
                                 trajectory=self._trajectory.writer.merged,
                                 events=self._events.writer.merged)
            # the kept tables (up to about 200 MB) are not needed once the logs are written
            self._trajectory.writer.merged = self._events.writer.merged = None
        self.summary_path = write_summary(result, self.folder,
                                          self.summary_extra(sim, logs, began))

    def summary_extra(self, sim: Simulation, logs: bool, began: float) -> dict[str, Any]:
        """The keys summary.json adds to ``RunResult.summary()``: the run's facts and its
        records (``logs``: per-robot logs written; ``began``: when writing began)."""
        counts = self._events.counts
        return {
            "run_uuid": self.run_info["uuid"], "created": self.run_info["created"],
            "mimics_version": self.run_info["mimics_version"], "policy": sim.policy,
            "time_limit": sim.time_limit, "wall_limit": sim.wall_limit,
            "deadlock_episodes": counts.get("deadlock", 0),
            "livelock_episodes": counts.get("livelock", 0),
            "user_messages": counts.get("user_message", 0),
            "edits": counts.get("edit", 0),
            "records": {"trajectory_rows": self._trajectory_rows,
                        "recorded_steps": self._trajectory.steps, "every": self.every,
                        "events": self._event_rows, "robot_logs": logs,
                        "scan_rows": self._scan_rows if self.record_scans else None,
                        "step_time": self._step_time,
                        "write_time": time.perf_counter() - began},
            **self.extra,
        }

    # -- hooks of an in-memory recorder (mimics.records.memory) ----------------

    def _writer(self, parts: str, schema: pa.Schema) -> PartWriter:
        """Where a table's parts go: files in the run folder's ``parts`` folder."""
        return PartWriter(self.folder / parts, schema, self.compression)

    def _open_folder(self) -> None:
        """Make the folder, removing an earlier run's records (never other files)."""
        prepare_run_folder(self.folder)

    def _write_scenario(self, scenario: Scenario) -> None:
        write_scenario_record(self.folder / SCENARIO_TOML, scenario, self.run_info)

    def _add_last_step(self, sim: Simulation) -> None:
        """Buffer the events of a run that ended within a step (user code stopped at the
        wall limit) and the last step, when ``every`` skipped it."""
        self._events.collect(sim.events, sim.state, np.zeros(0, dtype=np.int64))
        if self._full_step != sim.state.step:
            self._trajectory.add(sim.state, np.flatnonzero(sim.state.active))
            if self._scans is not None:
                self._scans.add(sim.state, np.flatnonzero(sim.state.active))

    # -- writing -------------------------------------------------------------

    def flush(self, last: bool = False) -> None:
        """Write the buffered rows and events as complete part files now.

        ``last``: the merge follows (a table that is a whole file then goes
        straight into it).
        """
        self._trajectory.flush(last=last)
        self._events.flush(last=last)
        if self._scans is not None:
            self._scans.flush(last=last)
        self._last_flush = time.perf_counter()

    def close(self, keep: bool = False) -> None:
        """Flush and merge the parts into trajectory.parquet and events.parquet.

        Called by ``on_end``; call it yourself when a run stops on an exception, to
        keep what was recorded (no summary.json is written then). ``keep``: hold
        the merged tables in the writers' ``merged`` (for the robot logs).
        """
        if self._closed or not self._started:
            return
        self._closed = True
        self.flush(last=True)
        self._merge(keep)

    def _close_with_logs(self, scenario: Scenario) -> None:
        """``close()`` and the robot logs, for a run still all in memory (one part).

        The logs are made from the buffered tables while another thread writes
        them as Parquet (whose encoding frees the GIL), rather than after it,
        from the files read back.
        """
        self._closed = True
        trajectory = self._trajectory.table()
        events = self._events.table()
        with ThreadPoolExecutor(1) as parquet:
            merged = parquet.submit(self._flush_and_merge, trajectory, events)
            write_robot_logs(
                self.folder, scenario, self.run_info,
                trajectory=empty_table(TRAJECTORY_SCHEMA) if trajectory is None else trajectory,
                events=empty_table(EVENTS_SCHEMA) if events is None else events)
            merged.result()

    def _flush_and_merge(self, trajectory: pa.Table | None, events: pa.Table | None) -> None:
        """Write the buffers' last parts (already built as these tables), then merge."""
        self._trajectory.flush(trajectory)
        self._events.flush(events)
        if self._scans is not None:
            self._scans.flush()
        self._merge()

    def _merge(self, keep: bool = False) -> None:
        """Merge the parts into trajectory.parquet, events.parquet (and scans.parquet)."""
        self._trajectory_rows = self._trajectory.writer.merge(self.folder / TRAJECTORY, keep)
        self._event_rows = self._events.writer.merge(self.folder / EVENTS, keep)
        if self._scans is not None:
            self._scan_rows = self._scans.writer.merge(self.folder / SCANS)

    @property
    def buffered_rows(self) -> int:
        """Trajectory rows held in memory, not yet written."""
        return self._trajectory.rows

    @property
    def finished(self) -> bool:
        """True once summary.json is written."""
        return self.summary_path is not None and (self.folder / SUMMARY_JSON).exists()
