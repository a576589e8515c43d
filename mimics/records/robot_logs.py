"""Per-robot text logs in the paper's form (section 3.8, Listing 2): the writer
(the reader and the rows of the format: ``robot_log_reader``).

``robots/robot_0000.log`` is robot 0, the engine's 0-based index (the same
number as the ``robot`` column of trajectory.parquet and events.parquet, and
the ``robot id`` of the header). Each log is::

    scenario = line
    algorithm = go_to_goal
    creation time = 2025-03-01T16:53:42+01:00
    log uuid = 5f0c...
    robot id = 0
    type = Pioneer3AT
    vehicle width = 0.5
    vehicle length = 0.7
    seed = 1

    time;x_gt;y_gt;phi_gt;v_gt;w_gt;x;y;phi;v_ref;phi_ref;user_msg;sys_msg
    [s];[m];[m];[rad];[m/s];[rad/s];[m];[m];[rad];[m/s];[rad];[];[]
    0;0;1;0;0;0;0;1;0;0;0;;
    0.1;0.0027;1;0;0.0525;0;0.0027;1;0;1;0;;
    ...

    Deactivation: Reached goal

The logs are written from the trajectory and events tables once the run has
ended (never in the step loop): by the recorder from the tables it holds,
while it writes them as trajectory.parquet and events.parquet, or from those
files, so ``mimics logs export RUN`` writes the very same files later. Numbers
are written in their shortest exact form (what ``repr`` gives): parsing a log
gives back the values of trajectory.parquet exactly. ``x``, ``y``, ``phi`` are
the positioning sensor's pose; the ``_gt`` columns are the ground truth. A
message holding ``;``, a quote or a line break is quoted as in CSV (RFC 4180).
``sys_msg`` is the engine's events of that step joined by `` | ``. The
creation time and the uuid are the run's, so the log uuid of robot i is the
same whenever its log is written.
"""

from __future__ import annotations

import uuid
from collections.abc import Iterable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow as pa
import pyarrow.parquet as pq

from mimics.engine.state import Status
from mimics.records.arrow_columns import numpy_column, string_array
from mimics.records.arrow_compute import join_element_wise
from mimics.records.events import EVENTS_SCHEMA
from mimics.records.layout import (
    EVENTS,
    EVENTS_PARTS,
    ROBOTS_DIR,
    TRAJECTORY,
    TRAJECTORY_PARTS,
    robot_log_name,
)
from mimics.records.log_texts import number_texts, same_bits, time_texts
from mimics.records.parts import part_files, read_table
from mimics.records.robot_log_reader import (  # the reader, and the format's rows
    DEACTIVATION,
    LOG_COLUMNS,
    LOG_UNITS,
    RobotLog,
    read_robot_log,
)
from mimics.records.trajectory import TRAJECTORY_SCHEMA
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario

__all__ = ["DEACTIVATION", "LOG_COLUMNS", "LOG_UNITS", "RobotLog", "header_lines", "log_uuid",
           "read_robot_log", "write_robot_logs"]

#: The trajectory.parquet column behind each numeric log column.
SOURCE_COLUMNS = ("time", "x", "y", "theta", "v", "w", "x_meas", "y_meas", "theta_meas",
                  "v_ref", "heading_ref")
STATUS_KIND = {Status.REACHED_GOAL: "reached_goal", Status.COLLIDED: "collision",
               Status.ESCAPED: "escaped", Status.DEADLOCK: "deadlock",
               Status.ERROR: "exception", Status.REMOVED: "edit"}
_SPECIAL = (";", '"', "\n", "\r")
WRITERS = 2  # threads that format and write the logs
GROUPS = 4  # groups of robots per batch: more than the threads, so writing overlaps formatting
_TRAJECTORY_SOURCE = ("robot", "step", "status", *SOURCE_COLUMNS)
_EVENTS_SOURCE = ("step", "robot", "kind", "detail")
#: Measured pose columns that usually repeat the true pose bit for bit (the heading always,
#: the position when the positioning sensor has no noise): then formatted once.
_COPIES = {"x_meas": "x", "y_meas": "y", "theta_meas": "theta"}


def log_uuid(run_uuid: str, robot: int) -> str:
    """The uuid of robot ``robot``'s log: derived from the run's, so stable across exports."""
    return str(uuid.uuid5(uuid.UUID(run_uuid), f"robot {robot}"))


def header_lines(scenario: Scenario, run: dict[str, Any], robot: int) -> list[str]:
    """The ``key = value`` header of robot ``robot``'s log."""
    kind = scenario.robot_type(robot)
    return [f"scenario = {scenario.name}", f"algorithm = {run.get('algorithm', '')}",
            f"creation time = {run.get('created', '')}",
            f"log uuid = {log_uuid(run['uuid'], robot) if run.get('uuid') else ''}",
            f"robot id = {robot}", f"type = {kind.name}", f"vehicle width = {kind.width!r}",
            f"vehicle length = {kind.length!r}", f"seed = {run.get('seed', '')}"]


def write_robot_logs(folder: Path, scenario: Scenario, run: dict[str, Any],
                     robots: Iterable[int] | None = None, out: Path | None = None,
                     batch_rows: int = 500_000, *, trajectory: pa.Table | None = None,
                     events: pa.Table | None = None) -> list[Path]:
    """Write the per-robot logs of the run in ``folder`` from its Parquet files (or tables).

    Robots are done in batches of about ``batch_rows`` trajectory rows, so memory
    stays bounded whatever the team size.

    Args:
        folder: the run folder (its trajectory and events, merged or in parts).
        scenario: the run's scenario (names, types and sizes for the headers).
        run: the run's facts: algorithm, seed, created, uuid.
        robots: robot indices to write (all by default).
        out: the folder for the logs (default: ``folder/robots``).
        batch_rows: trajectory rows read at once.
        trajectory: the run's whole trajectory table, when the caller holds it in
            memory (the recorder, for a run written as one part): used instead of
            reading it back from ``folder``.
        events: likewise, the run's whole events table.

    Returns:
        The paths written, in robot order.

    Raises:
        MimicsError: when a robot index is out of range or a file is unreadable.
    """
    n = scenario.robot_count
    wanted = sorted(set(range(n) if robots is None else (int(r) for r in robots)))
    bad = [r for r in wanted if not 0 <= r < n]
    if bad:
        raise MimicsError(f"robot {bad[0]}: no such robot (the run has robots 0..{n - 1})")
    folder = Path(folder)
    out = Path(out) if out is not None else folder / ROBOTS_DIR
    out.mkdir(parents=True, exist_ok=True)
    rows = trajectory.num_rows if trajectory is not None else _trajectory_rows(folder)
    size = max(1, batch_rows // max(1, rows // n))
    written: list[Path] = []
    with ThreadPoolExecutor(WRITERS) as pool:  # Arrow's casts and file writes free the GIL
        for first in range(0, len(wanted), size):
            batch = wanted[first:first + size]
            batch_trajectory, batch_events = _batch_tables(folder, batch, n, trajectory, events)
            written.extend(_write_batch(pool, _BatchLogs.of(batch_trajectory, batch_events, batch,
                                                            out, scenario, run)))
    return written


def _trajectory_rows(folder: Path) -> int:
    final = folder / TRAJECTORY
    files = [final] if final.exists() else part_files(folder / TRAJECTORY_PARTS)
    return sum(pq.read_metadata(f).num_rows for f in files)


def _batch_tables(folder: Path, batch: list[int], robot_count: int,
                  trajectory: pa.Table | None, events: pa.Table | None
                  ) -> tuple[pa.Table, pa.Table]:
    """The trajectory and events rows of the robots in ``batch``: from the tables given,
    else read from ``folder`` (no filter when the batch is every robot of the run)."""
    wanted = None  # every robot of the run (the recorder's usual case): no filter
    if len(batch) < robot_count:
        import pyarrow.compute as pc  # lazily: 60-100 ms to import, for a filter only

        wanted = pc.field("robot").isin(batch)
    if trajectory is None:
        trajectory = read_table(folder / TRAJECTORY, folder / TRAJECTORY_PARTS,
                                TRAJECTORY_SCHEMA, columns=_TRAJECTORY_SOURCE, filters=wanted)
    else:
        trajectory = trajectory.select(list(_TRAJECTORY_SOURCE))
        trajectory = trajectory if wanted is None else trajectory.filter(wanted)
    if events is None:
        events = read_table(folder / EVENTS, folder / EVENTS_PARTS, EVENTS_SCHEMA,
                            columns=_EVENTS_SOURCE, filters=wanted)
    else:
        events = events.select(list(_EVENTS_SOURCE))
        events = events if wanted is None else events.filter(wanted)
    return trajectory, events


@dataclass(frozen=True)
class _BatchLogs:
    """What the logs of a batch of robots are made of, rows sorted by robot then step.

    Attributes:
        robots: the robots of the batch, ascending.
        first: for each of ``robots``, the index of its first row.
        end: for each of ``robots``, one past the index of its last row.
        order: the trajectory rows in that order (row ``i`` is ``numbers[...][order[i]]``).
        steps: the ``step`` column, sorted.
        status: the ``status`` column, sorted.
        numbers: the numeric log columns as they were, by trajectory column name
            (gathered in order by each group's thread, as the work is shared out),
            less the measured pose columns that repeat the true pose bit for bit.
        copies: those columns left out, each with the column it repeats.
        messages: per robot, ``(step, user_msg, sys_msg)`` of its steps with messages.
        deactivations: the detail of each robot's last event of each kind.
        out: the folder for the logs.
        scenario: the run's scenario.
        run: the run's facts.
    """

    robots: list[int]
    first: np.ndarray
    end: np.ndarray
    order: np.ndarray
    steps: np.ndarray
    status: np.ndarray
    numbers: dict[str, np.ndarray]
    copies: dict[str, str]
    messages: dict[int, list[tuple[int, str, str]]]
    deactivations: dict[tuple[int, str], str]
    out: Path
    scenario: Scenario
    run: dict[str, Any]

    @classmethod
    def of(cls, table: pa.Table, events: pa.Table, robots: list[int], out: Path,
           scenario: Scenario, run: dict[str, Any]) -> _BatchLogs:
        """Sort ``table`` (the trajectory rows of ``robots``) and gather their ``events``."""
        ids = numpy_column(table["robot"])
        steps = numpy_column(table["step"])
        order = np.lexsort((steps, ids))
        ids, steps = ids[order], steps[order]
        messages, deactivations = _event_texts(events)
        numbers = {name: numpy_column(table[name]) for name in SOURCE_COLUMNS}
        # compared once for the batch, before any gather: a copy is then neither gathered
        # nor compared again by each group (its text is its source's)
        copies = {name: source for name, source in _COPIES.items()
                  if same_bits(numbers[name], numbers[source])}
        return cls(robots=robots, first=np.searchsorted(ids, robots, "left"),
                   end=np.searchsorted(ids, robots, "right"), order=order, steps=steps,
                   status=numpy_column(table["status"])[order],
                   numbers={name: values for name, values in numbers.items()
                            if name not in copies}, copies=copies,
                   messages=messages, deactivations=deactivations, out=out, scenario=scenario,
                   run=run)


def _write_batch(pool: ThreadPoolExecutor, batch: _BatchLogs) -> list[Path]:
    """The logs of ``batch``, in groups of robots of about equal rows, formatted and
    written by ``pool``'s threads: while one thread writes files, another formats."""
    cuts = np.searchsorted(batch.first, np.linspace(0, batch.end[-1], GROUPS + 1)[1:-1])
    groups = [group for group in np.split(np.arange(len(batch.robots)), cuts) if group.size]
    return [path for paths in pool.map(partial(_write_group, batch), groups) for path in paths]


def _write_group(batch: _BatchLogs, group: np.ndarray) -> list[Path]:
    """Write the logs of the robots ``batch.robots[group]`` (consecutive); returns their paths."""
    start, stop = int(batch.first[group[0]]), int(batch.end[group[-1]])
    block, offsets = _lines(batch, start, stop)
    n = batch.scenario.robot_count
    paths = []
    for k in group:
        robot, a, b = batch.robots[k], int(batch.first[k]), int(batch.end[k])
        lines = offsets[a - start:b - start + 1]  # where the robot's lines start, and its end
        rows: bytes | memoryview = block[lines[0]:lines[-1]]
        if robot in batch.messages:
            rows = _with_messages(block, lines, batch.steps[a:b], batch.messages[robot])
        final = Status(int(batch.status[b - 1])) if b > a else Status.ACTIVE
        ending = (batch.deactivations.get((robot, STATUS_KIND[final]), final.label)
                  if final != Status.ACTIVE else "None (active when the run ended)")
        head = "\n".join([*header_lines(batch.scenario, batch.run, robot), "",
                          ";".join(LOG_COLUMNS), ";".join(LOG_UNITS)]) + "\n"
        tail = "\n" + DEACTIVATION + " ".join(ending.split()) + "\n"
        path = batch.out / robot_log_name(robot, n)
        with path.open("wb") as file:  # in turn: the lines (130 kB a robot) are not copied
            file.write(head.encode())    # into one bytes first
            file.write(rows)
            file.write(tail.encode())
        paths.append(path)
    return paths


def _with_messages(block: memoryview, lines: np.ndarray, steps: np.ndarray,
                   messages: list[tuple[int, str, str]]) -> bytes:
    """One robot's lines (``block[lines[0]:lines[-1]]``, a line per entry of ``steps``)
    with the message fields of ``messages`` (sorted by step) filled in.

    Only the lines with messages are touched: each ends with its two empty
    fields, ``;;`` and the line break, which the messages replace.
    """
    pieces = []
    done = int(lines[0])
    for step, user, system in messages:
        i = int(np.searchsorted(steps, step))
        if i < len(steps) and steps[i] == step:
            end = int(lines[i + 1])
            pieces.append(block[done:end - 3])
            pieces.append(f";{_quoted(user)};{_quoted(system)}\n".encode())
            done = end
    pieces.append(block[done:int(lines[-1])])
    return b"".join(pieces)


def _lines(batch: _BatchLogs, start: int, stop: int) -> tuple[memoryview, np.ndarray]:
    """Rows ``start:stop`` as ``;``-separated lines ending with two empty message fields.

    Returns the lines as one UTF-8 block and the offset where each line starts
    (one more for the end), both counted from row ``start``.
    """
    if stop == start:
        return memoryview(b""), np.zeros(1, dtype=np.int32)
    rows = batch.order[start:stop]
    numbers = {name: values[rows] for name, values in batch.numbers.items()}
    texts = {"time": time_texts(numbers["time"], batch.steps[start:stop])}
    for name in SOURCE_COLUMNS[1:]:
        source = _COPIES.get(name)
        texts[name] = (texts[source] if source and (
            name in batch.copies or same_bits(numbers[name], numbers[source]))
            else number_texts(numbers[name]))
    # Arrow scalars taken from an array: a Python str argument would import pandas
    empty, newline, separator = string_array(["", "\n", ";"])
    lines = join_element_wise(*texts.values(), empty, newline, separator)
    _, offsets, data = lines.buffers()
    return memoryview(data), np.frombuffer(offsets, np.int32, len(lines) + 1, lines.offset * 4)


def _event_texts(events: pa.Table
                 ) -> tuple[dict[int, list[tuple[int, str, str]]], dict[tuple[int, str], str]]:
    """From ``events``: per robot, ``(step, user_msg, sys_msg)`` of the steps with messages;
    and the detail of each robot's last event of each kind."""
    user: dict[tuple[int, int], str] = {}
    system: dict[tuple[int, int], list[str]] = {}
    override: dict[tuple[int, int], str] = {}
    last: dict[tuple[int, str], str] = {}
    for row in events.to_pylist():
        key = (row["robot"], row["step"])
        if row["kind"] == "user_message":
            user[key] = row["detail"]
        elif row["kind"] == "system_message":
            override[key] = row["detail"]
        else:
            system.setdefault(key, []).append(row["detail"])
            last[(row["robot"], row["kind"])] = row["detail"]
    messages: dict[int, list[tuple[int, str, str]]] = {}
    for key in sorted(set(user) | set(system) | set(override)):
        sys_text = override.get(key, " | ".join(system.get(key, ())))
        messages.setdefault(key[0], []).append((key[1], user.get(key, ""), sys_text))
    return messages, last


def _quoted(text: str) -> str:
    """A message as a field: quoted as in CSV when it holds ``;``, a quote or a line break."""
    if any(c in text for c in _SPECIAL):
        return '"' + text.replace('"', '""') + '"'
    return text
