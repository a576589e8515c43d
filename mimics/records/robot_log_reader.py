"""The reader of the per-robot text logs (``robot_logs`` writes them; its docstring shows
the form), and the rows that define the form."""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from mimics.world.errors import MimicsError

if TYPE_CHECKING:  # pandas costs ~0.3 s to import: only the reader needs it, when called
    import pandas as pd

LOG_COLUMNS = ("time", "x_gt", "y_gt", "phi_gt", "v_gt", "w_gt", "x", "y", "phi", "v_ref",
               "phi_ref", "user_msg", "sys_msg")
LOG_UNITS = ("[s]", "[m]", "[m]", "[rad]", "[m/s]", "[rad/s]", "[m]", "[m]", "[rad]", "[m/s]",
             "[rad]", "[]", "[]")
DEACTIVATION = "Deactivation: "


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


def read_robot_log(path: str | Path) -> RobotLog:
    """Parse a per-robot log back into its header, table and deactivation.

    Raises:
        MimicsError: naming the file, when it is not a log in this form.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise MimicsError(f"{path}: cannot read ({exc.strerror})") from None
    except UnicodeDecodeError as exc:
        raise MimicsError(f"{path}: not a robot log (not UTF-8 text: {exc.reason})") from None
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
    import pandas as pd

    table = pd.DataFrame(rows, columns=list(LOG_COLUMNS))
    for name in LOG_COLUMNS[:-2]:
        table[name] = table[name].astype(np.float64)
    return RobotLog(header=header, columns=tuple(names.split(";")),
                    units=tuple(units.split(";")), table=table,
                    deactivation=ending.rstrip("\n"))
