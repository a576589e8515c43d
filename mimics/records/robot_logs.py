"""Per-robot text logs in the paper's form (section 3.8, Listing 2), and their reader.

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

The logs are written from trajectory.parquet and events.parquet once the run
has ended (never in the step loop), so ``mimics logs export RUN`` writes the
very same files later. Numbers are written in their shortest exact form (what
``repr`` gives): parsing a log gives back the values of trajectory.parquet
exactly. ``x``, ``y``, ``phi`` are the positioning sensor's pose; the ``_gt``
columns are the ground truth. A message holding ``;``, a quote or a line break
is quoted as in CSV (RFC 4180). ``sys_msg`` is the engine's events of that
step joined by `` | ``. The creation time and the uuid are the run's, so the
log uuid of robot i is the same whenever its log is written.
"""

from __future__ import annotations

import csv
import io
import uuid
from collections.abc import Iterable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.csv as pacsv
import pyarrow.parquet as pq

from mimics.engine.state import Status
from mimics.records.events import EVENTS_SCHEMA
from mimics.records.layout import (
    EVENTS,
    EVENTS_PARTS,
    ROBOTS_DIR,
    TRAJECTORY,
    TRAJECTORY_PARTS,
    robot_log_name,
)
from mimics.records.parts import part_files, read_table
from mimics.records.trajectory import TRAJECTORY_SCHEMA
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario

LOG_COLUMNS = ("time", "x_gt", "y_gt", "phi_gt", "v_gt", "w_gt", "x", "y", "phi", "v_ref",
               "phi_ref", "user_msg", "sys_msg")
LOG_UNITS = ("[s]", "[m]", "[m]", "[rad]", "[m/s]", "[rad/s]", "[m]", "[m]", "[rad]", "[m/s]",
             "[rad]", "[]", "[]")
#: The trajectory.parquet column behind each numeric log column.
SOURCE_COLUMNS = ("time", "x", "y", "theta", "v", "w", "x_meas", "y_meas", "theta_meas",
                  "v_ref", "heading_ref")
DEACTIVATION = "Deactivation: "
STATUS_KIND = {Status.REACHED_GOAL: "reached_goal", Status.COLLIDED: "collision",
               Status.ESCAPED: "escaped", Status.DEADLOCK: "deadlock",
               Status.ERROR: "exception"}
_CSV_OPTIONS = pacsv.WriteOptions(include_header=False, delimiter=";", quoting_style="none")
_SPECIAL = (";", '"', "\n", "\r")
WRITERS = 2  # threads that format and write the logs


@dataclass(frozen=True)
class RobotLog:
    """A parsed per-robot log.

    Attributes:
        header: the ``key = value`` lines, values as text.
        columns: the names row.
        units: the units row.
        table: one row per recorded step; numbers as float64, messages as text.
        deactivation: the text after ``Deactivation:``.
    """

    header: dict[str, str]
    columns: tuple[str, ...]
    units: tuple[str, ...]
    table: pd.DataFrame
    deactivation: str


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
                     batch_rows: int = 500_000) -> list[Path]:
    """Write the per-robot logs of the run in ``folder`` from its Parquet files.

    Robots are done in batches of about ``batch_rows`` trajectory rows, so memory
    stays bounded whatever the team size.

    Args:
        folder: the run folder (its trajectory and events, merged or in parts).
        scenario: the run's scenario (names, types and sizes for the headers).
        run: the run's facts: algorithm, seed, created, uuid.
        robots: robot indices to write (all by default).
        out: the folder for the logs (default: ``folder/robots``).
        batch_rows: trajectory rows read at once.

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
    out = Path(out) if out is not None else Path(folder) / ROBOTS_DIR
    out.mkdir(parents=True, exist_ok=True)
    per_robot = max(1, _trajectory_rows(Path(folder)) // n)
    size = max(1, batch_rows // per_robot)
    written: list[Path] = []
    with ThreadPoolExecutor(WRITERS) as pool:  # Arrow's CSV writer and file writes free the GIL
        for first in range(0, len(wanted), size):
            written.extend(_write_batch(pool, folder, out, scenario, run,
                                        wanted[first:first + size]))
    return written


def _write_batch(pool: ThreadPoolExecutor, folder: Path, out: Path, scenario: Scenario,
                 run: dict[str, Any], batch: list[int]) -> list[Path]:
    """The logs of the robots in ``batch``, formatted and written with ``pool``'s threads."""
    n = scenario.robot_count
    folder = Path(folder)
    table = read_table(folder / TRAJECTORY, folder / TRAJECTORY_PARTS,
                       TRAJECTORY_SCHEMA, columns=("robot", "step", "status", *SOURCE_COLUMNS),
                       filters=pc.field("robot").isin(batch))
    table = table.sort_by([("robot", "ascending"), ("step", "ascending")])
    messages, deactivations = _event_texts(folder, batch)
    block, starts = _numeric_block(table, pool)
    ids = table["robot"].to_numpy()
    steps = table["step"].to_numpy()
    status = table["status"].to_numpy()
    files: list[tuple[Path, bytes]] = []
    for robot in batch:
        a, b = np.searchsorted(ids, robot, "left"), np.searchsorted(ids, robot, "right")
        rows = block[starts[a]:starts[b]]  # one line per row, each ending in ";;\n"
        if robot in messages:
            lines = rows.decode().split("\n")[:-1]
            for step, user, system in messages[robot]:
                k = int(np.searchsorted(steps[a:b], step))
                if k < len(lines) and steps[a + k] == step:
                    lines[k] = f"{lines[k][:-2]};{_quoted(user)};{_quoted(system)}"
            rows = "".join(line + "\n" for line in lines).encode()
        final = Status(int(status[b - 1])) if b > a else Status.ACTIVE
        ending = (deactivations.get((robot, STATUS_KIND[final]), final.label)
                  if final != Status.ACTIVE else "None (active when the run ended)")
        head = "\n".join([*header_lines(scenario, run, robot), "", ";".join(LOG_COLUMNS),
                          ";".join(LOG_UNITS)]) + "\n"
        tail = "\n" + DEACTIVATION + " ".join(ending.split()) + "\n"
        files.append((out / robot_log_name(robot, n), head.encode() + rows + tail.encode()))
    list(pool.map(lambda item: item[0].write_bytes(item[1]), files))
    return [path for path, _ in files]


def _trajectory_rows(folder: Path) -> int:
    final = folder / TRAJECTORY
    files = [final] if final.exists() else part_files(folder / TRAJECTORY_PARTS)
    return sum(pq.read_metadata(f).num_rows for f in files)


def _csv_bytes(table: pa.Table) -> bytes:
    sink = io.BytesIO()
    pacsv.write_csv(table, sink, _CSV_OPTIONS)
    return sink.getvalue()


def _numeric_block(table: pa.Table, pool: ThreadPoolExecutor) -> tuple[bytes, np.ndarray]:
    """The numeric columns as ``;``-separated lines ending with two empty message fields.

    Returns the lines as one UTF-8 block and the offset where each line starts
    (one more for the end). Slices of the table are formatted by ``pool``'s
    threads: Arrow writes CSV outside the GIL, and writing the numbers is most
    of the cost of the logs.
    """
    numeric = table.select(list(SOURCE_COLUMNS))
    empty = pa.nulls(table.num_rows, pa.string())
    numeric = numeric.append_column("user_msg", empty).append_column("sys_msg", empty)
    size = max(1, -(-numeric.num_rows // WRITERS))
    slices = [numeric.slice(first, size) for first in range(0, numeric.num_rows, size)]
    block = b"".join(pool.map(_csv_bytes, slices))
    ends = np.flatnonzero(np.frombuffer(block, dtype=np.uint8) == ord("\n")) + 1
    return block, np.concatenate([[0], ends])


def _event_texts(folder: Path, robots: list[int]
                 ) -> tuple[dict[int, list[tuple[int, str, str]]], dict[tuple[int, str], str]]:
    """For ``robots``: per robot, ``(step, user_msg, sys_msg)`` of the steps with messages;
    and the detail of each robot's last event of each kind."""
    events = read_table(folder / EVENTS, folder / EVENTS_PARTS, EVENTS_SCHEMA,
                        columns=("step", "robot", "kind", "detail"),
                        filters=pc.field("robot").isin(robots)).to_pylist()
    user: dict[tuple[int, int], str] = {}
    system: dict[tuple[int, int], list[str]] = {}
    override: dict[tuple[int, int], str] = {}
    last: dict[tuple[int, str], str] = {}
    for row in events:
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


def read_robot_log(path: str | Path) -> RobotLog:
    """Parse a per-robot log back into its header, table and deactivation.

    Raises:
        MimicsError: naming the file, when it is not a log in this form.
    """
    path = Path(path)
    try:
        text = path.read_text()
    except OSError as exc:
        raise MimicsError(f"{path}: cannot read ({exc.strerror})") from None
    head, sep, rest = text.partition("\n\n")
    names, _, rest = rest.partition("\n")
    units, _, rest = rest.partition("\n")
    body, found, ending = rest.rpartition("\n" + DEACTIVATION)
    if not sep or not found or tuple(names.split(";")) != LOG_COLUMNS:
        raise MimicsError(f"{path}: not a per-robot log (expected a header, the row "
                          f"{';'.join(LOG_COLUMNS)}, a units row and a Deactivation line)")
    header = {}
    for line in head.split("\n"):
        key, _, value = line.partition(" = ")
        header[key] = value
    rows = list(csv.reader(io.StringIO(body.rstrip("\n")), delimiter=";"))
    if any(len(row) != len(LOG_COLUMNS) for row in rows):
        raise MimicsError(f"{path}: a table row does not have {len(LOG_COLUMNS)} fields")
    table = pd.DataFrame(rows, columns=list(LOG_COLUMNS))
    for name in LOG_COLUMNS[:-2]:
        table[name] = table[name].astype(np.float64)
    return RobotLog(header=header, columns=tuple(names.split(";")),
                    units=tuple(units.split(";")), table=table,
                    deactivation=ending.rstrip("\n"))
