"""Recording a run in memory: the run folder's tables without the folder, saved on request.

:class:`MemoryRecorder` is the :class:`~mimics.records.recorder.RunRecorder`
with its part files kept as tables in memory (:class:`MemoryPartWriter`):
the same buffers make the same rows of trajectory.parquet and events.parquet,
but nothing is written. :class:`MemoryRun` reads like a loaded run folder
(:class:`mimics.records.run_folder.Run`: ``summary``, ``trajectory``,
``events``, ``scenario``, ``robot(i)``), so that every reader of a run (the
plot, the replay) takes it; :func:`save_run` writes it as a run folder that
``mimics report``, ``mimics replay`` and ``mimics.load_run`` read.

>>> from mimics.records.runner import prepare
>>> sim = prepare("line", "go_to_goal", robots=2, time=1.0, seed=1)
>>> recorder = MemoryRecorder()
>>> sim.observers.append(recorder)
>>> run = MemoryRun(recorder, sim.run())
>>> len(run.trajectory) == 2 * (run.summary["steps"] + 1), run.path
(True, None)
"""

from __future__ import annotations

import math
import time
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc

from mimics.engine.outcome import RunResult
from mimics.records.arrow_columns import empty_table
from mimics.records.events import EVENTS_SCHEMA
from mimics.records.layout import (
    EVENTS,
    EVENTS_PARTS,
    SCENARIO_TOML,
    TRAJECTORY,
    TRAJECTORY_PARTS,
)
from mimics.records.parts import PartWriter
from mimics.records.recorder import (
    AUTO_ROBOT_LOGS,
    RobotLogs,
    RunRecorder,
    check_save_target,
    prepare_run_folder,
)
from mimics.records.robot_logs import write_robot_logs
from mimics.records.run_folder import Run
from mimics.records.scenario_record import write_scenario_record
from mimics.records.summary import write_summary
from mimics.records.trajectory import TRAJECTORY_SCHEMA
from mimics.world.errors import MimicsError
from mimics.world.output_paths import as_path

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation
    from mimics.world.scenario import Scenario


class MemoryPartWriter(PartWriter):
    """A :class:`PartWriter` whose parts stay in memory; ``merge`` concatenates them
    into ``merged`` (and writes nothing)."""

    def __init__(self, schema: pa.Schema) -> None:
        super().__init__(Path("."), schema)  # the folder is never used
        self._tables: list[pa.Table] = []

    def write(self, table: pa.Table, last: bool = False) -> None:
        """Keep ``table`` as the next part (nothing for an empty table)."""
        if table.num_rows == 0:
            return
        self._tables.append(table)
        self.parts += 1
        self.rows += table.num_rows

    def merge(self, target: Path, keep: bool = False) -> int:
        """Concatenate the parts into ``merged`` (``target`` is ignored); returns its rows."""
        self.merged = (pa.concat_tables(self._tables).combine_chunks() if self._tables
                       else empty_table(self.schema))
        self._tables = []
        return int(self.merged.num_rows)


class MemoryRecorder(RunRecorder):
    """Records one simulation in memory (an observer: pass it in ``observers``).

    The rows are those a :class:`RunRecorder` writes; at the end ``trajectory``
    and ``events`` hold them as Arrow tables, ``scenario`` and ``run_info``
    what scenario.toml would hold, and ``extra`` the keys summary.json adds.

    Args:
        every: record every ``every``-th step in full (deactivations and the last
            step always).
        extra: keys added to the summary.
    """

    def __init__(self, *, every: int = 1, extra: dict[str, Any] | None = None) -> None:
        # no per-robot logs and no timed flushes: the parts are tables in memory
        super().__init__("<memory>", robot_logs="off", every=every, flush_seconds=math.inf,
                         extra=extra)
        self.scenario: Scenario | None = None
        self.trajectory: pa.Table | None = None
        self.events: pa.Table | None = None
        self.summary_keys: dict[str, Any] = {}

    def _writer(self, parts: str, schema: pa.Schema) -> PartWriter:
        return MemoryPartWriter(schema)

    def _open_folder(self) -> None:
        """Nothing to open: the records stay in memory."""

    def _write_scenario(self, scenario: Scenario) -> None:
        self.scenario = scenario

    def on_end(self, sim: Simulation, result: RunResult) -> None:
        """Concatenate the rows into ``trajectory`` and ``events``; keep the summary keys."""
        if self._closed:
            return
        began = time.perf_counter()
        self.scenario = sim.scenario  # with the edits made during the run, if any
        self._add_last_step(sim)
        self.close()
        self.trajectory = self._trajectory.writer.merged
        self.events = self._events.writer.merged
        self._trajectory.writer.merged = self._events.writer.merged = None
        self.summary_keys = self.summary_extra(sim, False, began)


class MemoryRun(Run):
    """A run recorded in memory, read as a loaded run folder (``path`` is None).

    Args:
        recorder: the recorder of the finished run.
        result: the run's outcome.
    """

    def __init__(self, recorder: MemoryRecorder, result: RunResult) -> None:
        if recorder.trajectory is None or recorder.events is None or recorder.scenario is None:
            raise MimicsError("MemoryRun: the recorder has not seen the run end")
        self.path = None  # type: ignore[assignment]
        self.result = result
        self.trajectory_table: pa.Table = recorder.trajectory
        self.events_table: pa.Table = recorder.events
        self.summary_keys = dict(recorder.summary_keys)
        self._scenario_info = (recorder.scenario, dict(recorder.run_info))

    def __repr__(self) -> str:
        return f"MemoryRun({self._described()})"

    @property
    def complete(self) -> bool:
        """Always True: a memory run exists once its simulation has ended."""
        return True

    @cached_property
    def summary(self) -> dict[str, Any]:
        """What summary.json would hold."""
        return {**self.result.summary(), **self.summary_keys}

    @cached_property
    def _record(self) -> tuple[Scenario, dict[str, Any]]:
        return self._scenario_info

    def read_trajectory(self, columns: list[str] | None = None,
                        robots: list[int] | None = None,
                        arrow: bool = False) -> pd.DataFrame | pa.Table:
        """The trajectory, or some of its columns or robots (as :meth:`Run.read_trajectory`)."""
        table = self.trajectory_table
        if robots is not None:
            table = table.filter(pc.is_in(table["robot"],
                                          pa.array([int(r) for r in robots], pa.int32())))
        if columns is not None:
            table = table.select(list(columns))
        return table if arrow else table.to_pandas()

    def read_events(self, kinds: list[str] | None = None,
                    arrow: bool = False) -> pd.DataFrame | pa.Table:
        """The events, or only those of some kinds (as :meth:`Run.read_events`)."""
        table = self.events_table
        if kinds is not None:
            table = table.filter(pc.is_in(table["kind"], pa.array(list(kinds), pa.string())))
        return table if arrow else table.to_pandas()

    @property
    def has_scans(self) -> bool:
        """False: scans are recorded only into a run folder (``record_scans`` with ``out``)."""
        return False

    def log_path(self, i: int) -> Path:
        """Refused: a run in memory has no logs until saved."""
        raise MimicsError("this run is in memory: save it with .save(FOLDER) to get its logs")


def save_run(run: MemoryRun, folder: str | Path, *, robot_logs: RobotLogs = "auto") -> Path:
    """Write ``run`` as a run folder, as a :class:`RunRecorder` would have written it.

    Args:
        run: the run in memory.
        folder: the run folder (created; an earlier run's records in it are replaced).
        robot_logs: per-robot text logs: ``"auto"`` (up to 200 robots), ``"on"``, ``"off"``.

    Returns:
        The folder.

    Raises:
        MimicsError: when the folder holds other files than a run's, or cannot be written;
            nothing is written then.
    """
    if robot_logs not in ("auto", "on", "off"):
        raise MimicsError(f"robot_logs: expected auto, on or off, got {robot_logs!r}")
    out = as_path("save: folder", folder)
    check_save_target(out)
    prepare_run_folder(out)
    scenario, info = run._record
    began = time.perf_counter()
    try:
        write_scenario_record(out / SCENARIO_TOML, scenario, info)
        for table, parts, final, schema in (
                (run.trajectory_table, TRAJECTORY_PARTS, TRAJECTORY, TRAJECTORY_SCHEMA),
                (run.events_table, EVENTS_PARTS, EVENTS, EVENTS_SCHEMA)):
            writer = PartWriter(out / parts, schema)  # the recorder's own file writing
            writer.write(table, last=True)
            writer.merge(out / final)
        logs = robot_logs == "on" or (robot_logs == "auto"
                                      and scenario.robot_count <= AUTO_ROBOT_LOGS)
        if logs:
            write_robot_logs(out, scenario, info, trajectory=run.trajectory_table,
                             events=run.events_table)
    except OSError as exc:
        raise MimicsError(f"{out}: cannot write the run folder here "
                          f"({exc.strerror or exc})") from None
    records = {**run.summary_keys.get("records", {}), "robot_logs": logs,
               "write_time": time.perf_counter() - began}
    write_summary(run.result, out, {**run.summary_keys, "records": records})
    return out
