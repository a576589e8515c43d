"""Reading a run folder back: ``mimics.load_run(path)``.

A run folder (written by :class:`mimics.records.recorder.RunRecorder`, through
``mimics run``, ``mimics.simulate(..., out=...)`` or a battery)::

    runs/line-go_to_goal-s1/
      scenario.toml        what was run (scenario, types, map, settings, [run] table)
      trajectory.parquet   one row per robot per recorded step (see trajectory.py)
      events.parquet       events and messages (see events.py)
      scans.parquet        the laser scans, when recorded (see scans.py)
      robots/robot_0000.log  per-robot logs in the paper's form, 0-based (robot_logs.py)
      summary.txt          the outcome for a person
      summary.json         the outcome for a program: written last, marks a finished run

A run killed midway has no summary.json and keeps its data in
``trajectory.parts/`` and ``events.parts/`` (complete Parquet files, read as
one table); :attr:`Run.complete` tells the two apart. Loading reads only
summary.json and the Parquet footers; the trajectory, the events and the
scenario are read on first use, and never the per-robot text logs.

>>> import tempfile, mimics
>>> folder = tempfile.mkdtemp()
>>> _ = mimics.simulate("line", "go_to_goal", robots=2, seed=1, out=folder,
...                     params={"random_yaw": False})
>>> run = mimics.load_run(folder)
>>> run.summary["reached_goal"], run.complete, len(run.robot(1)) == run.summary["steps"] + 1
(2, True, True)
"""

from __future__ import annotations

import json
from functools import cached_property
from pathlib import Path
from typing import Any

import pandas as pd
import pyarrow as pa
import pyarrow.compute as pc
import pyarrow.parquet as pq

from mimics.records.events import EVENTS_SCHEMA
from mimics.records.layout import (
    EVENTS,
    EVENTS_PARTS,
    ROBOTS_DIR,
    SCANS,
    SCANS_PARTS,
    SCENARIO_TOML,
    SUMMARY_JSON,
    TRAJECTORY,
    TRAJECTORY_PARTS,
    robot_log_name,
)
from mimics.records.parts import check_readable, one_line, part_files, read_table
from mimics.records.scans import SCANS_SCHEMA, ScanLayout, ScanRecord
from mimics.records.scenario_record import read_scenario_record
from mimics.records.summary import summary_rows
from mimics.records.trajectory import TRAJECTORY_SCHEMA
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario


class Run:
    """A recorded run, read lazily from its folder (use ``load_run``).

    Attributes:
        path: the run folder.
    """

    def __init__(self, path: Path) -> None:
        self.path = Path(path)

    def __repr__(self) -> str:
        return f"Run({str(self.path)!r}: {self._described()})"

    def _described(self) -> str:
        """Scenario, algorithm, seed, robots and status, as the reprs show them."""
        s = self.summary
        return (f"{s.get('scenario')} / {s.get('algorithm')} / seed {s.get('seed')}, "
                f"{s.get('robots')} robots, {s.get('status')}")

    @property
    def complete(self) -> bool:
        """True when the run finished and was fully recorded (summary.json exists)."""
        return (self.path / SUMMARY_JSON).is_file()

    @cached_property
    def summary(self) -> dict[str, Any]:
        """summary.json as a dict; for a killed run, ``status: "incomplete"`` and what
        scenario.toml tells (scenario, algorithm, seed, robots)."""
        if self.complete:
            path = self.path / SUMMARY_JSON
            try:
                data = json.loads(path.read_text())
            except (OSError, ValueError) as exc:
                raise MimicsError(f"{path}: not a readable summary ({exc})") from None
            if not isinstance(data, dict):
                raise MimicsError(f"{path}: not a readable summary (expected a JSON object)")
            check_summary_types(data, path)
            return data
        run = self.info
        return {"status": "incomplete", "scenario": self.scenario.name,
                "algorithm": run.get("algorithm", "?"), "seed": run.get("seed", "?"),
                "robots": self.scenario.robot_count, "created": run.get("created"),
                "run_uuid": run.get("uuid"), "mimics_version": run.get("mimics_version")}

    @cached_property
    def _record(self) -> tuple[Scenario, dict[str, Any]]:
        return read_scenario_record(self.path / SCENARIO_TOML)

    @property
    def scenario(self) -> Scenario:
        """The scenario that was run (map, robot types, stages, goals, settings)."""
        return self._record[0]

    @property
    def info(self) -> dict[str, Any]:
        """The ``[run]`` table of scenario.toml: seed, algorithm, policy, limits, version,
        creation time and uuid."""
        return self._record[1]

    @cached_property
    def trajectory(self) -> pd.DataFrame:
        """All rows of trajectory.parquet as a DataFrame (read once, then kept)."""
        return self.read_trajectory()

    def read_trajectory(self, columns: list[str] | None = None,
                        robots: list[int] | None = None,
                        arrow: bool = False) -> pd.DataFrame | pa.Table:
        """Read the trajectory, or some of its columns or robots.

        Args:
            columns: columns to read (all by default).
            robots: robot indices to keep (all by default).
            arrow: return a ``pyarrow.Table`` instead of a DataFrame.

        Raises:
            MimicsError: naming the file, when it is truncated or unreadable.
        """
        filters = None if robots is None else pc.field("robot").isin([int(r) for r in robots])
        table = read_table(self.path / TRAJECTORY, self.path / TRAJECTORY_PARTS,
                           TRAJECTORY_SCHEMA, columns=columns, filters=filters)
        return table if arrow else table.to_pandas()

    @cached_property
    def events(self) -> pd.DataFrame:
        """All rows of events.parquet as a DataFrame (read once, then kept)."""
        return self.read_events()

    def read_events(self, kinds: list[str] | None = None,
                    arrow: bool = False) -> pd.DataFrame | pa.Table:
        """Read the events, or only those of some kinds (``["collision", "deadlock"]``).

        Raises:
            MimicsError: naming the file, when it is truncated or unreadable.
        """
        filters = None if kinds is None else pc.field("kind").isin(list(kinds))
        table = read_table(self.path / EVENTS, self.path / EVENTS_PARTS, EVENTS_SCHEMA,
                           filters=filters)
        return table if arrow else table.to_pandas()

    @property
    def has_scans(self) -> bool:
        """True when the run recorded its laser scans (``--record-scans``)."""
        return (self.path / SCANS).exists() or bool(part_files(self.path / SCANS_PARTS))

    @cached_property
    def scans(self) -> ScanRecord:
        """The recorded laser scans (read once, then kept): see ``mimics.records.scans``.

        Raises:
            MimicsError: when the run did not record them, or the file is unreadable.
        """
        if not self.has_scans:
            raise MimicsError(f"{self.path}: no laser scans recorded in this run (run it with "
                              f"--record-scans, or record_scans=True)")
        final = self.path / SCANS
        first = final if final.exists() else part_files(self.path / SCANS_PARTS)[0]
        try:
            metadata = pq.read_schema(first).metadata
        except (pa.ArrowException, OSError) as exc:
            raise MimicsError(f"{first}: not a readable Parquet file, truncated or corrupt "
                              f"({one_line(exc)})") from None
        layout = ScanLayout.from_metadata(metadata, str(first))
        table = read_table(final, self.path / SCANS_PARTS, SCANS_SCHEMA)
        return ScanRecord(table, layout)

    def robot(self, i: int) -> pd.DataFrame:
        """Robot ``i``'s rows of the trajectory (0-based index), in step order.

        Raises:
            MimicsError: when the run has no robot ``i``.
        """
        self._check_robot(i)
        frame = self.read_trajectory(robots=[i])
        return frame.sort_values("step", kind="stable").reset_index(drop=True)

    def log_path(self, i: int) -> Path:
        """Where robot ``i``'s text log is (or would be written by ``mimics logs export``)."""
        self._check_robot(i)
        return self.path / ROBOTS_DIR / robot_log_name(i, self.robot_count)

    @property
    def robot_count(self) -> int:
        """Number of robots of the run."""
        robots = self.summary.get("robots") if self.complete else None
        return int(robots) if isinstance(robots, int) else self.scenario.robot_count

    def _check_robot(self, i: int) -> None:
        n = self.robot_count
        if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < n:
            raise MimicsError(f"robot {i!r}: no such robot (the run has robots 0..{n - 1})")


#: Keys of summary.json read as numbers (None allowed: a run with no speed, no wall limit).
NUMBER_KEYS = ("robots", "sim_time", "wall_time", "steps", "sim_speed", "reached_goal",
               "collisions", "robot_collisions", "wall_collisions", "escaped", "deadlocks",
               "livelocks", "exceptions", "active_at_end", "collided_at_end", "time_limit",
               "wall_limit", "deadlock_episodes", "livelock_episodes", "user_messages")
NULLABLE_KEYS = ("sim_speed", "wall_limit", "active_at_end")
#: Keys of summary.json read as tables of numbers (mean, min, max...; None allowed).
TABLE_KEYS = ("user_code_time", "time_to_goal", "path_length", "path_efficiency")


def check_summary_types(data: dict[str, Any], path: Path) -> None:
    """Refuse a summary.json whose known keys hold values of the wrong type, in one line.

    Raises:
        MimicsError: naming the file, the key and what was expected.
    """
    def number(value: Any, nullable: bool = True) -> bool:
        return ((nullable and value is None)
                or (isinstance(value, int | float) and not isinstance(value, bool)))

    for key in NUMBER_KEYS:
        if key in data and not number(data[key], key in NULLABLE_KEYS):
            raise MimicsError(f"{path}: not a readable summary ({key}: expected a number, got "
                              f"{data[key]!r})")
    for key in (*TABLE_KEYS, "records"):
        table = data.get(key, {})
        if not isinstance(table, dict) or (key != "records" and not all(
                number(v) for v in table.values())):
            raise MimicsError(f"{path}: not a readable summary ({key}: expected a table of "
                              f"numbers, got {table!r})")
    records = data.get("records", {})
    for key in ("trajectory_rows", "step_time", "write_time"):
        if key in records and not number(records[key]):
            raise MimicsError(f"{path}: not a readable summary (records.{key}: expected a "
                              f"number, got {records[key]!r})")
    try:
        summary_rows(data)  # what `mimics report` and summary.txt show must be showable
    except (TypeError, ValueError, KeyError, AttributeError) as exc:
        raise MimicsError(f"{path}: not a readable summary ({type(exc).__name__}: {exc})"
                          ) from None


def load_run(path: str | Path) -> Run:
    """Open a run folder; its files are read when first used.

    Args:
        path: the folder written by a run.

    Returns:
        A :class:`Run` with ``.summary``, ``.trajectory``, ``.events``,
        ``.scenario``, ``.robot(i)`` and, when recorded, ``.scans``.

    Raises:
        MimicsError: in one line naming the folder or file, when the folder is
            not a run, or summary.json or a Parquet file is unreadable or truncated.
    """
    folder = Path(path)
    if not folder.is_dir():
        what = "it is a file" if folder.exists() else "no such directory"
        raise MimicsError(f"{folder}: not a run folder ({what})")
    if not (folder / SUMMARY_JSON).is_file() and not (folder / SCENARIO_TOML).is_file():
        raise MimicsError(f"{folder}: not a run folder (no {SUMMARY_JSON} or {SCENARIO_TOML})")
    run = Run(folder)
    _ = run.summary  # a broken summary.json fails here, in one line
    for final, parts, schema in ((TRAJECTORY, TRAJECTORY_PARTS, TRAJECTORY_SCHEMA),
                                 (EVENTS, EVENTS_PARTS, EVENTS_SCHEMA)):
        if (folder / final).exists():
            check_readable(folder / final, schema)
        elif run.complete:
            raise MimicsError(f"{folder / final}: missing (summary.json says the run finished)")
        else:
            for part in part_files(folder / parts):
                check_readable(part, schema)
    if (folder / SCANS).exists():
        check_readable(folder / SCANS, SCANS_SCHEMA)
    return run
