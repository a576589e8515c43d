"""The columns a battery table shows by default, the rest one argument away.

The report's tables have a column per count and interval bound (22 to 30):
wider than a notebook cell. ``BatteryView.summary()``, ``.intervals()`` and
``.compare()`` show the columns a first reading needs; ``columns="all"`` gives
every one, a list of names those.

>>> import pandas as pd
>>> table = pd.DataFrame({"algorithm": ["a"], "runs": [2], "wall_time": [0.1]})
>>> list(chosen(table, None, ("algorithm", "runs"), "summary"))
['algorithm', 'runs']
>>> list(chosen(table, "all", ("algorithm",), "summary"))
['algorithm', 'runs', 'wall_time']
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import pandas as pd

from mimics.world.errors import MimicsError

#: Who the rows are about, first in every table.
CELL = ("algorithm", "scenario", "parameters")
#: ``summary()``: the runs and the two counts a reader looks at first, with their intervals.
SUMMARY = (*CELL, "runs", "failed", "reached_goal", "reached_goal_ci95", "collisions",
           "collisions_ci95")
#: ``compare()``: the difference, its interval and the adjusted p-value.
COMPARE = ("algorithm", "baseline", "scenario", "parameters", "metric", "pairs",
           "mean_difference", "ci95_low", "ci95_high", "p_adjusted")
#: ``intervals()``: metrics shown by default (those the table has, in this order).
INTERVAL_METRICS = ("success", "time_to_goal")


def interval_columns(table: pd.DataFrame, metrics: Sequence[str] | None) -> tuple[str, ...]:
    """The default columns of ``intervals()``: each metric's estimate and bounds (the
    metrics asked for, else success and time to goal)."""
    shown = list(metrics) if metrics else [m for m in INTERVAL_METRICS if m in table]
    if not shown:  # a battery without goals: its first metric
        shown = [c for c in table.columns if f"{c}_low" in table][:2]
    return (*CELL, "runs", "failed",
            *(c for m in shown for c in (m, f"{m}_low", f"{m}_high")))


def chosen(table: pd.DataFrame, columns: Any, default: Sequence[str], what: str
           ) -> pd.DataFrame:
    """``table`` with ``columns``: None the ``default`` ones it has, ``"all"`` every one,
    a list those (in that order).

    Raises:
        MimicsError: ``columns`` is none of these, or names a column the table lacks.
    """
    if columns is None:
        return table[[c for c in default if c in table.columns]]
    if isinstance(columns, str):
        if columns != "all":
            raise MimicsError(f"{what}: columns: expected None, 'all' or a list of column "
                              f"names, got {columns!r}")
        return table
    if not isinstance(columns, list | tuple) or not all(isinstance(c, str) for c in columns):
        raise MimicsError(f"{what}: columns: expected None, 'all' or a list of column names, "
                          f"got {columns!r}")
    missing = [c for c in columns if c not in table.columns]
    if missing and not table.empty:
        raise MimicsError(f"{what}: columns: no column {missing[0]!r} (expected some of: "
                          f"{', '.join(map(str, table.columns))})")
    return table[[c for c in columns if c in table.columns]]
