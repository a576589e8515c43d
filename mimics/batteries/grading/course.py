"""A class's grades from a battery: the marks with a reason each, keyed by student id,
the feedback files and the leaderboard.

:func:`grade_class` applies the teacher's ``grade(runs)`` (see
:mod:`mimics.batteries.grading`), then adds to each row ``student_id`` (and
``name``) from the class list, ``reason`` (one sentence, unless ``grade`` gave
its own), ``time_to_goal`` (the tie-break of the leaderboard) and ``copy_of``;
a student of the class list without a submission gets mark 0 and the reason
"no submission". :func:`write_class` writes ``marks.csv``,
``feedback/<student_id>.md`` and ``leaderboard.csv``/``.html``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from mimics.batteries.grading import Grader, marks
from mimics.batteries.grading.feedback import write_feedback
from mimics.batteries.grading.leaderboard import leaderboard, write_leaderboard
from mimics.batteries.grading.outcomes import reason
from mimics.batteries.grading.students import Student

NO_SUBMISSION = "no submission"


@dataclass(frozen=True)
class ClassGrades:
    """What :func:`grade_class` found.

    Attributes:
        table: one row per student: ``student_id``, ``name`` (with a class list that
            has names), ``student`` (the file's stem), the grader's columns, ``mark``,
            ``reason``, ``time_to_goal``, ``copy_of``.
        runs: the battery's runs table it was computed from.
        base: the battery file's folder (submissions are named relative to it).
    """

    table: pd.DataFrame
    runs: pd.DataFrame
    base: Path | None


def grade_class(runs: pd.DataFrame, grader: Grader, *, where: str = "grade",
                students: list[Student] | None = None,
                base: Path | None = None) -> ClassGrades:
    """The class table: the grader's marks with ids, reasons, times and copies.

    Raises:
        MimicsError: the grader failed or returned no usable marks (see
            :func:`mimics.batteries.grading.marks`).
    """
    graded = marks(runs, grader, where=where)
    frame = graded.reset_index() if "student" not in graded.columns else graded.reset_index(
        drop=True)
    if "student" not in frame.columns:  # the grader's index had another name (or none)
        frame = frame.rename(columns={frame.columns[0]: "student"})
    frame["student"] = frame["student"].astype(str)
    by_student = dict(tuple(runs.groupby("algorithm"))) if not runs.empty else {}
    own = [str(r) for r in frame.get("reason", pd.Series([""] * len(frame)))]
    frame["reason"] = [
        text if text and text != "nan" else reason(
            by_student.get(name, runs.iloc[0:0]), base)
        for text, name in zip(own, frame["student"], strict=True)]
    times = mean_times(runs)
    frame["time_to_goal"] = [times.get(name, math.nan) for name in frame["student"]]
    roster = {s.stem: s for s in students or []}
    frame.insert(0, "student_id", [roster[s].student_id if s in roster else s
                                   for s in frame["student"]])
    if any(s.name for s in roster.values()):
        frame.insert(1, "name", [roster[s].name if s in roster else "" for s in frame["student"]])
    missing = [s for stem, s in roster.items() if stem not in set(frame["student"])]
    if missing:
        extra = pd.DataFrame({"student_id": [s.student_id for s in missing],
                              "student": [s.stem for s in missing], "mark": 0.0,
                              "reason": NO_SUBMISSION, "time_to_goal": math.nan})
        if "name" in frame.columns:
            extra["name"] = [s.name for s in missing]
        if "copy_of" in frame.columns:
            extra["copy_of"] = ""
        whole = [c for c in frame.columns if pd.api.types.is_integer_dtype(frame[c])]
        frame = pd.concat([frame, extra], ignore_index=True)
        frame[whole] = frame[whole].astype("Int64")  # counts stay whole, empty where no runs
    ordered = [c for c in ("student_id", "name", "student") if c in frame.columns]
    tail = [c for c in ("reason", "time_to_goal", "copy_of") if c in frame.columns]
    rest = [c for c in frame.columns if c not in ordered and c not in tail]
    return ClassGrades(frame[[*ordered, *rest, *tail]], runs, base)


def mean_times(runs: pd.DataFrame) -> dict[str, float]:
    """Per submission, the mean over its runs of the time to goal: each run's mean over its
    robots, a robot that did not arrive counting the run's horizon; a run that did not
    finish counts the longest horizon of its scenario and parameters (it brought no robot
    home). NaN when no run of the submission has a time."""
    if runs.empty or "time_to_goal" not in runs.columns:
        return {}
    table = runs.assign(_time=pd.to_numeric(runs["time_to_goal"], errors="coerce"),
                        _horizon=pd.to_numeric(runs.get("horizon"), errors="coerce"))
    cells = [c for c in ("scenario", "label") if c in table.columns]
    longest = table.groupby(cells)["_horizon"].transform("max") if cells else table["_horizon"]
    failed = table["state"] != "done"
    table.loc[failed, "_time"] = longest[failed]
    return {str(name): float(group["_time"].mean())
            for name, group in table.groupby("algorithm")}


def write_class(grades: ClassGrades, folder: Path, marks_csv: Path,
                title: str = "leaderboard") -> list[Path]:
    """``marks.csv`` at ``marks_csv``; ``feedback/`` and ``leaderboard.csv``/``.html`` in
    ``folder``. Returns the paths written.

    Raises:
        MimicsError: a file cannot be written, naming it.
    """
    from mimics.world.errors import MimicsError

    table = grades.table.copy()
    table["time_to_goal"] = table["time_to_goal"].round(2)
    try:
        table.to_csv(marks_csv, index=False)
    except OSError as exc:
        raise MimicsError(f"--marks {marks_csv}: cannot write it ({exc.strerror})") from None
    feedback = write_feedback(grades.table, grades.runs, folder, grades.base)
    board = write_leaderboard(leaderboard(grades.table), folder, title)
    return [marks_csv, feedback, *board]
