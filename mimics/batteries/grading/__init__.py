"""Marks from a battery: a teacher's grading function applied to its top-tier table.

A grading file is a Python file with a function ``grade(runs)`` that takes the
battery's table (:func:`mimics.batteries.report.runs_table`: one row per run,
with ``algorithm``, ``scenario``, ``seed``, ``state`` and the counts
``robots``, ``reached_goal``, ``collisions``...) and returns a DataFrame with
one row per student (or algorithm) and at least a numeric ``mark`` column.
``mimics battery report BATTERY --grade grade.py`` prints the marks and writes
them as CSV.

Copies are flagged (:func:`flag_copies`): submissions whose code is the same once
comments, blank lines and spacing are dropped, or whose runs all finished with the
same digests (identical trajectories), get a ``copy_of`` column naming the others.

The course's workflow on top of the marks (a reason per mark, student ids from a
class list, feedback files, the leaderboard) is :mod:`.course`.
"""

from __future__ import annotations

import hashlib
import io
import math
import runpy
import tokenize
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
    return flag_copies(result, runs)


def code_hash(path: str | Path) -> str:
    """A hash of a Python file's code without its comments, blank lines and spacing (""
    when it cannot be read or tokenized)."""
    try:
        text = Path(path).read_text(encoding="utf-8", errors="replace")
        tokens = [t.string for t in tokenize.generate_tokens(io.StringIO(text).readline)
                  if t.type not in (tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE,
                                    tokenize.INDENT, tokenize.DEDENT, tokenize.ENDMARKER)]
    except (OSError, SyntaxError, tokenize.TokenError, IndentationError):
        return ""
    return hashlib.sha256("\x00".join(tokens).encode()).hexdigest()


def flag_copies(marks_table: pd.DataFrame, runs: pd.DataFrame) -> pd.DataFrame:
    """``marks_table`` with ``copy_of``: the other submissions with the same code or the
    same trajectories ("" for none). Rows are matched to runs by the index's values
    (or a ``student`` column) as the ``algorithm`` column names them."""
    if "algorithm" not in runs.columns or runs.empty:
        return marks_table
    same: dict[str, set[str]] = {}
    for key in ("code", "digests"):
        groups: dict[str, list[str]] = {}
        for name, rows in runs.groupby("algorithm"):
            value = _fingerprint(rows, key)
            if value:
                groups.setdefault(value, []).append(str(name))
        for names in groups.values():
            for name in names:
                same.setdefault(name, set()).update(n for n in names if n != name)
    result = marks_table.copy()
    keys = (result["student"] if "student" in result.columns else result.index.to_series())
    result["copy_of"] = [", ".join(sorted(same.get(str(k), ()))) for k in keys]
    return result


def _fingerprint(rows: pd.DataFrame, key: str) -> str:
    """A submission's code hash, or its runs' digests in order (all runs done and digested)."""
    if key == "code":
        refs = rows["algorithm_ref"] if "algorithm_ref" in rows.columns else pd.Series([])
        paths = [r for r in refs.dropna().unique() if str(r).endswith(".py")]
        return code_hash(paths[0]) if len(paths) == 1 else ""
    if "digest" not in rows.columns:
        return ""
    if "state" in rows.columns and not (rows["state"] == "done").all():
        # two submissions that fail at the same first step leave the same trajectories:
        # that is the same failure, not a copy
        return ""
    order = [c for c in ("scenario", "parameters", "seed") if c in rows.columns]
    ordered = rows.sort_values(order) if order else rows
    digests = [str(d) for d in ordered["digest"].tolist() if isinstance(d, str) and d]
    if len(digests) != len(ordered) or not digests:
        return ""
    return hashlib.sha256("|".join([*map(str, ordered[order].astype(str).values.ravel()),
                                    *digests]).encode()).hexdigest()
