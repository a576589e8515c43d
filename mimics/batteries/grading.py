"""Marks from a battery: a teacher's grading function applied to its top-tier table.

A grading file is a Python file with a function ``grade(runs)`` that takes the
battery's table (:func:`mimics.batteries.report.runs_table`: one row per run,
with ``algorithm``, ``scenario``, ``seed``, ``state`` and the counts
``robots``, ``reached_goal``, ``collisions``...) and returns a DataFrame with
one row per student (or algorithm) and at least a numeric ``mark`` column.
``mimics battery report BATTERY --grade grade.py`` prints the marks and writes
them as CSV.
"""

from __future__ import annotations

import math
import runpy
from collections.abc import Callable
from pathlib import Path

import pandas as pd

from mimics.world.errors import MimicsError

Grader = Callable[[pd.DataFrame], pd.DataFrame]


def load_grader(path: str | Path) -> Grader:
    """The ``grade`` function of a grading file.

    Raises:
        MimicsError: the file is missing, does not import, or has no ``grade`` function.
    """
    path = Path(path)
    if not path.is_file():
        raise MimicsError(f"grading file {path} does not exist")
    try:
        namespace = runpy.run_path(str(path))
    except SyntaxError as exc:
        raise MimicsError(f"{path}, line {exc.lineno}: syntax error: {exc.msg}") from None
    except Exception as exc:  # the teacher's code at import time: one line
        raise MimicsError(f"{path}: importing it raised {type(exc).__name__}: {exc}") from None
    grade = namespace.get("grade")
    if not callable(grade):
        raise MimicsError(f"{path}: expected a function grade(runs) returning a DataFrame "
                          "with a 'mark' column")
    return grade


def marks(runs: pd.DataFrame, grader: Grader, where: str = "grade") -> pd.DataFrame:
    """Apply ``grader`` to the runs table and check what it returns.

    Raises:
        MimicsError: the grader raised, or did not return a DataFrame with a finite
            numeric ``mark`` column.
    """
    try:
        result = grader(runs.copy())
    except Exception as exc:
        raise MimicsError(f"{where}: grade(runs) raised {type(exc).__name__}: {exc}") from None
    if not isinstance(result, pd.DataFrame) or "mark" not in result.columns:
        raise MimicsError(f"{where}: grade(runs) must return a DataFrame with a 'mark' column, "
                          f"got {type(result).__name__}")
    values = pd.to_numeric(result["mark"], errors="coerce")
    if values.isna().any() or not all(math.isfinite(v) for v in values):
        raise MimicsError(f"{where}: grade(runs) returned marks that are not finite numbers")
    return result
