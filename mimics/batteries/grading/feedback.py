"""A feedback file per student: the mark, its reason, each run's outcome and the first error.

``feedback/<student_id>.md`` in the battery folder, Markdown a student can read
as plain text::

    # Feedback for s1234567 (Alice Martin)

    - File: submissions/alice.py
    - Mark: 6.7
    - Reason: raised ValueError at submissions/alice.py:12 on seed 2 (crossroads); ...

    ## Your runs
    | scenario | seed | outcome | robots home | collisions | time to goal (s) |
    ...

    ## First error
    ...
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import pandas as pd

from mimics.batteries.grading.outcomes import battery_order, first_error, shown_path
from mimics.world.errors import MimicsError

FEEDBACK_DIR = "feedback"
_UNSAFE = re.compile(r"[^A-Za-z0-9._-]+")
_OUTCOMES = {"completed": "ended: every robot home or stopped",
             "time_limit": "ran to the time limit", "goals_reached": "every robot home"}


def feedback_name(student_id: str) -> str:
    """The feedback file's name for an id: letters, digits, ``._-`` only, never hidden.

    >>> feedback_name("../s 1<script>")
    '_s_1_script_.md'
    """
    safe = _UNSAFE.sub("_", student_id).lstrip(".") or "student"
    return f"{safe[:100]}.md"


def feedback_text(row: dict[str, Any], runs: pd.DataFrame, base: Path | None) -> str:
    """The feedback of one row of the class table, from that submission's runs."""
    who = str(row.get("student_id") or row.get("student") or "")
    name = str(row.get("name") or "")
    lines = [f"# Feedback for {_inline(who)}" + (f" ({_inline(name)})" if name else ""), ""]
    if runs.empty:
        lines += [f"- Mark: {_mark(row.get('mark'))}", "- Reason: no submission", "",
                  "No file of yours was in the battery: nothing was run.", ""]
        return "\n".join(lines)
    refs = runs["algorithm_ref"].dropna().unique() if "algorithm_ref" in runs else []
    if len(refs):
        lines.append(f"- File: {_inline(shown_path(str(refs[0]), base))}")
    lines += [f"- Mark: {_mark(row.get('mark'))}", f"- Reason: {_inline(str(row.get('reason')))}",
              "", "## Your runs", "",
              "| scenario | parameters | seed | outcome | robots home | collisions | "
              "time to goal (s) |", "|---|---|---|---|---|---|---|"]
    for run in battery_order(runs).to_dict("records"):
        lines.append("| " + " | ".join(_cell(v) for v in (
            run.get("scenario"), run.get("label"), run.get("seed"), _outcome(run),
            _home(run), _count(run.get("collisions")), _seconds(run.get("time_to_goal")))) + " |")
    lines += ["", "Time to goal: the mean over the run's robots of the time each took to reach "
              "its goal; a robot that did not arrive counts the run's whole time.", ""]
    site = first_error(runs, base)
    if site is not None:
        lines += ["## First error", "", f"{_sentence_case(_inline(site.sentence()))}.", ""]
        if site.line:
            lines += [f"{_inline(site.file)}, line {site.line}:", "",
                      f"    {site.line} | {site.source}", ""]
        if site.message:
            lines += ["Message:", "", f"    {site.message}", ""]
    return "\n".join(lines)


def write_feedback(table: pd.DataFrame, runs: pd.DataFrame, folder: Path,
                   base: Path | None) -> Path:
    """One feedback file per row of the class table in ``folder/feedback``; feedback
    files of an earlier report that this one does not write again are removed.

    Raises:
        MimicsError: the folder or a file cannot be written.
    """
    out = folder / FEEDBACK_DIR
    by_student = dict(tuple(runs.groupby("algorithm"))) if not runs.empty else {}
    written: set[str] = set()
    try:
        out.mkdir(exist_ok=True)
        for row in table.to_dict("records"):
            name = feedback_name(str(row.get("student_id") or row.get("student")))
            if name in written:  # two ids that only differ in unsafe characters
                name = f"{name[:-3]}-{row.get('student')}.md"
            own = by_student.get(str(row.get("student")), runs.iloc[0:0])
            if row.get("reason") == "no submission":
                own = runs.iloc[0:0]
            (out / name).write_text(feedback_text(row, own, base), encoding="utf-8")
            written.add(name)
        for old in out.glob("*.md"):
            if old.name not in written:
                old.unlink()
    except OSError as exc:
        raise MimicsError(f"{out}: cannot write the feedback files ({exc.strerror})") from None
    return out


def _outcome(run: dict[str, Any]) -> str:
    state, status = str(run.get("state") or ""), run.get("status")
    if state == "done":
        return _OUTCOMES.get(str(status), f"done ({status})" if isinstance(status, str) else "done")
    return {"error": "failed: an error", "timeout": "stopped: time-out",
            "crashed": "crashed"}.get(state, state)


def _home(run: dict[str, Any]) -> str:
    if run.get("state") != "done":
        return "-"
    robots = run.get("goal_robots")
    robots = run.get("robots") if _absent(robots) else robots
    return f"{_count(run.get('reached_goal'))} of {_count(robots)}"


def _count(value: Any) -> str:
    return "-" if _absent(value) else str(int(value))


def _seconds(value: Any) -> str:
    return "-" if _absent(value) else f"{float(value):.1f}"


def _mark(value: Any) -> str:
    return "-" if _absent(value) else f"{float(value):g}"


def _absent(value: Any) -> bool:
    return value is None or value is pd.NA or (isinstance(value, float) and math.isnan(value))


def _inline(text: str) -> str:
    """A value on one line (a student's text cannot start a new Markdown block)."""
    return " ".join(str(text).split())


def _sentence_case(text: str) -> str:
    return text[:1].upper() + text[1:]


def _cell(value: Any) -> str:
    return "-" if _absent(value) or value == "" else _inline(str(value)).replace("|", "\\|")
