"""The names of the files in a run folder, in one place.

A run folder holds (see ``docs`` of :mod:`mimics.records.run_folder`)::

    scenario.toml        what was run: scenario, types, map, settings, [run] table
    trajectory.parquet   one row per robot per recorded step (the source of truth)
    events.parquet       deactivations, collisions, stalls, exceptions, messages
    scans.parquet        the laser scans, only when recorded (``--record-scans``)
    robots/robot_0000.log  one text log per robot (0-based robot index), optional
    summary.txt          the outcome for a person
    summary.json         the outcome for a program; written last: it marks a finished run

While a run goes on, trajectory, events (and scans) are written as numbered part files
(``trajectory.parts/part-000000.parquet``...), each complete with its footer,
and merged into the single files when the run ends. A run killed midway keeps
its part files, which :func:`mimics.load_run` reads as one table.

>>> robot_log_name(7, robots=10)
'robot_0007.log'
>>> robot_log_name(12345, robots=20000)
'robot_12345.log'
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path

from mimics.world.errors import MimicsError
from mimics.world.output_paths import Folder, is_inside, same_file

#: Trajectory rows a recorder buffers before it writes them as a part (``flush_rows``):
#: about 300 MB at a flush (``resources.ROW_BYTES``). Most runs fit in one part (the
#: paper's 600 s Cave: 600,000 rows), written once; several parts are encoded again
#: when merged, which cost the Cave's run 290 ms of 1,030 of recording.
FLUSH_ROWS = 1_048_576

SUMMARY_JSON = "summary.json"
SUMMARY_TXT = "summary.txt"
SCENARIO_TOML = "scenario.toml"
TRAJECTORY = "trajectory.parquet"
TRAJECTORY_PARTS = "trajectory.parts"
EVENTS = "events.parquet"
EVENTS_PARTS = "events.parts"
SCANS = "scans.parquet"
SCANS_PARTS = "scans.parts"
ROBOTS_DIR = "robots"

#: Every name a recorder writes; a new run in an old folder removes these first.
RECORD_NAMES = (SUMMARY_JSON, SUMMARY_TXT, SCENARIO_TOML, TRAJECTORY, TRAJECTORY_PARTS, EVENTS,
                EVENTS_PARTS, SCANS, SCANS_PARTS, ROBOTS_DIR)


def robot_log_name(robot: int, robots: int) -> str:
    """File name of robot ``robot``'s text log (0-based index, at least 4 digits).

    Args:
        robot: the engine's robot index, from 0.
        robots: number of robots in the run (more than 10000 widens the number).
    """
    digits = max(4, len(str(max(robots - 1, 0))))
    return f"robot_{robot:0{digits}d}.log"


def run_records(folder: str | os.PathLike[str], *, but: tuple[str, ...] = ()) -> Folder:
    """A run folder as an input of :func:`mimics.world.output_paths.check_outputs`: no
    output may be one of its records (``but`` those the command rewrites itself)."""
    return Folder(folder, tuple(name for name in RECORD_NAMES if name not in but))


def check_run_output(name: str, folder: str | os.PathLike[str],
                     inputs: Mapping[str, str | os.PathLike[str] | None]) -> None:
    """Refuse a folder to record a run in when it is an input, or when one of the records a
    run there replaces is, or holds, an input (``mimics run R/scenario.toml ... --out R``).

    Raises:
        MimicsError: one line naming the option, the folder and the input.
    """
    out = Path(folder)
    for what, given in inputs.items():
        if given is None or str(given) == "":
            continue
        source = Path(given)
        if same_file(out, source):
            raise MimicsError(f"{name} {out}: is {what} that this command reads (expected a "
                              "new folder, or an earlier run's)")
        for record in RECORD_NAMES:
            if same_file(out / record, source) or is_inside(source, out / record):
                raise MimicsError(f"{name} {out}: a run there replaces {out / record}, which is "
                                  f"{what} that this command reads (expected another folder)")
