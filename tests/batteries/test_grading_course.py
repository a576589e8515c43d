"""The pure parts of a course's grading: reasons, class lists, the leaderboard, the class table.

Runs are written by hand as the battery's runs table would hold them (the error
and traceback texts are those the battery records; see
tests/examples/test_teaching_kit.py for the same through real runs), and every
expected sentence, order and value is worked out by hand from them.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pandas as pd
import pytest

from mimics.batteries.grading.course import grade_class, mean_times
from mimics.batteries.grading.feedback import feedback_name, feedback_text
from mimics.batteries.grading.leaderboard import leaderboard, leaderboard_html
from mimics.batteries.grading.outcomes import error_site, reason
from mimics.batteries.grading.students import Student, read_students
from mimics.world.errors import MimicsError


def _run(algorithm: str, seed: int, state: str = "done", *, robots: int = 4, reached: int = 4,
         collisions: int = 0, deadlocks: int = 0, time_to_goal: float = 20.0,
         error: str = "", traceback: str = "", ref: str = "", scenario: str = "crossroads",
         run_id: int = 0) -> dict[str, Any]:
    done = state == "done"
    return {"id": run_id or seed, "algorithm": algorithm, "algorithm_ref": ref or
            f"/class/submissions/{algorithm}.py", "scenario": scenario, "label": "",
            "seed": seed, "state": state, "status": "completed" if done else state,
            "robots": robots if done else None, "goal_robots": robots if done else None,
            "reached_goal": reached if done else None,
            "collisions": collisions if done else None, "deadlocks": deadlocks if done else None,
            "time_to_goal": time_to_goal if done else math.nan,
            "horizon": 60.0 if done else math.nan, "error": error, "traceback": traceback}


def _grade(runs: pd.DataFrame) -> pd.DataFrame:
    """A grading function: the share of robots home, out of 10, 0 for a failed run."""
    points = (10.0 * runs["reached_goal"].fillna(0).astype(float)
              / runs["robots"].fillna(1).astype(float)).where(runs["state"] == "done", 0.0)
    table = runs.assign(points=points, student=runs["algorithm"]).groupby("student").agg(
        runs=("points", "size"), mark=("points", "mean"))
    return table.round(1)


RAISED = ("ValueError in robot 0 at t=0.6 s, submissions/bob.py:12: boom\n"
          "    raise ValueError(\"boom\")")
RAISED_TRACE = ('Traceback (most recent call last):\n  File "/class/submissions/bob.py", line '
                '12, in step\n    raise ValueError("boom")\nValueError: boom\n')


#: (student, seed, state, the error the battery records) -> the sentence that explains it
FAILURES = {
    ("eve", 1, "timeout", "wall-clock timeout: robot 0: step() did not return within the wall "
     "limit of 2 s; stopped at step 0 (t=0 s), submissions/eve.py:7\n    while True:"):
    "stopped: step did not return within 2 s (submissions/eve.py:7) on seed 1 (crossroads)",
    ("sam", 1, "error", "the run could not start: /class/submissions/sam.py, line 3: syntax "
     "error: expected ':'"): "file did not load: SyntaxError at line 3 (expected ':')",
    ("ian", 1, "error", "the run could not start: /class/submissions/ian.py, line 1: importing "
     "it raised ModuleNotFoundError: No module named 'torch'"):
    "file did not load: ModuleNotFoundError at line 1 (No module named 'torch')",
    ("lou", 1, "timeout", "wall-clock timeout: /class/submissions/lou.py, line 5: importing it "
     "did not finish within 8 s (an endless loop outside step()?)"):
    "stopped: loading the file did not finish within 8 s (line 5)",
    ("kim", 3, "timeout", "wall-clock timeout: no result after 130.2 s (limit 120 s); the worker "
     "process was killed"):
    "stopped: the run took longer than 120 s of wall-clock time on seed 3 (crossroads)",
}


@pytest.mark.parametrize(("run", "sentence"), FAILURES.items(), ids=[k[0] for k in FAILURES])
def test_each_kind_of_failure_gets_its_own_sentence_with_its_line(
        run: tuple[str, int, str, str], sentence: str) -> None:
    student, seed, state, error = run
    site = error_site(_run(student, seed, state, error=error), Path("/class"))
    assert site.sentence() == sentence


def test_a_raised_exception_is_named_with_its_file_and_line() -> None:
    raised = _run("bob", 2, "error", error=RAISED, traceback=RAISED_TRACE)
    assert error_site(raised, Path("/class")).sentence() == (
        "raised ValueError at submissions/bob.py:12 on seed 2 (crossroads)")
    # a submission outside the battery's folder is named by its file name alone
    assert error_site(raised, Path("/elsewhere")).file == "bob.py"


def test_a_reason_counts_the_robots_home_the_collisions_and_the_failures() -> None:
    good = pd.DataFrame([_run("ann", s, reached=4 - (s == 2)) for s in (1, 2, 3)])
    assert reason(good) == "11 of 12 robots home without collision on 3 of 3 runs"
    bumpy = pd.DataFrame([_run("ann", 1), _run("ann", 2, collisions=2, reached=3)])
    assert reason(bumpy) == "7 of 8 robots home on 2 of 2 runs, with collisions in 1 of them"
    still = pd.DataFrame([_run("sid", s, reached=0, deadlocks=4) for s in (1, 2)])
    assert reason(still) == ("0 of 8 robots home without collision on 2 of 2 runs, "
                             "8 removed as deadlocked (no progress)")
    # the first failure in the battery's order (run ids), then what the others did
    mixed = pd.DataFrame([_run("bob", 1, run_id=1),
                          _run("bob", 3, "error", error=RAISED, run_id=3,
                               traceback=RAISED_TRACE.replace("line 12", "line 13")),
                          _run("bob", 2, "error", error=RAISED, traceback=RAISED_TRACE,
                               run_id=2)])
    assert reason(mixed, Path("/class")) == (
        "raised ValueError at submissions/bob.py:12 on seed 2 (crossroads); 2 of 3 runs failed; "
        "4 of 4 robots home without collision on the 1 finished runs")
    assert reason(pd.DataFrame(columns=["state"])) == "no submission"


def test_the_leaderboard_ranks_by_mark_then_time_and_shares_ranks_of_full_ties() -> None:
    table = pd.DataFrame({"student_id": ["d", "c", "b", "a", "e"],
                          "mark": [7.0, 9.0, 7.0, 7.0, 0.0],
                          "time_to_goal": [31.0, 50.0, 30.0, 31.0, math.nan],
                          "reason": ["r"] * 5})
    board = leaderboard(table)
    # 9 first; among the 7s, 30 s before 31 s; a and d tie on both: one rank, by id
    assert board[["rank", "student_id"]].values.tolist() == [
        [1, "c"], [2, "b"], [3, "a"], [3, "d"], [5, "e"]]


def test_the_leaderboard_page_escapes_what_students_named() -> None:
    evil = "<script>alert('x')</script>"
    board = leaderboard(pd.DataFrame({"student_id": [evil, "s2"], "mark": [5.0, 4.0],
                                      "time_to_goal": [1.0, 2.0],
                                      "reason": ["raised X at <img src=x onerror=y>.py:1",
                                                 "a & b"]}))
    page = leaderboard_html(board, "class <b>1</b>")
    assert "<script" not in page and "<img" not in page and "<b>1" not in page
    assert "&lt;script&gt;alert(&#x27;x&#x27;)&lt;/script&gt;" in page
    assert "a &amp; b" in page and "class &lt;b&gt;1&lt;/b&gt;" in page
    assert "http" not in page  # self-contained: nothing fetched
    assert feedback_name(evil) == "_script_alert_x_script_.md"
    assert feedback_name("..") == "student.md"


def test_a_class_list_keys_the_marks_and_lists_who_handed_nothing_in(tmp_path: Path) -> None:
    runs = pd.DataFrame([_run("alice", 1), _run("alice", 2, reached=2),
                         _run("carl", 1, reached=0)])
    listed = [Student("alice", "s100", "Alice"), Student("bob", "s200", "Bob")]
    table = grade_class(runs, _grade, students=listed).table.set_index("student")
    assert table.loc["alice", ["student_id", "name", "mark"]].tolist() == ["s100", "Alice", 7.5]
    assert table.loc["bob", ["student_id", "mark", "reason"]].tolist() == [
        "s200", 0.0, "no submission"]
    assert pd.isna(table.loc["bob", "runs"])
    assert table.loc["carl", ["student_id", "name"]].tolist() == ["carl", ""]  # no row: its stem
    assert table.loc["alice", "reason"] == "6 of 8 robots home without collision on 2 of 2 runs"
    assert list(grade_class(runs, _grade).table.columns[:2]) == ["student_id", "student"]
    rows = table.reset_index()
    bob = rows[rows["student_id"] == "s200"].iloc[0].to_dict()
    missing = feedback_text(bob, runs.iloc[0:0], None)
    assert "no submission" in missing and "s200 (Bob)" in missing


def test_mean_times_count_a_failed_run_at_its_cells_horizon() -> None:
    runs = pd.DataFrame([_run("a", 1, time_to_goal=20.0), _run("a", 2, time_to_goal=30.0),
                         _run("b", 1, time_to_goal=10.0), _run("b", 2, "error", error="x")])
    assert mean_times(runs) == {"a": 25.0, "b": 35.0}  # b: (10 + 60) / 2


def test_a_class_list_is_read_strictly(tmp_path: Path) -> None:
    path = tmp_path / "students.csv"
    path.write_text("\ufefffile,student_id,name\nsubmissions/alice.py, s1 ,Alice\n\nbob,s2,\n")
    assert read_students(path) == [Student("alice", "s1", "Alice"), Student("bob", "s2", "")]
    for text, expected in [("name,id\nalice.py,s1\n", "expected a header"),
                           ("file,student_id\nalice.py,s1\nalice.py,s2\n", "line 3: the file"),
                           ("file,student_id\nalice.py,s1\nbob.py,s1\n", "line 3: the student_id"),
                           ("file,student_id\nalice.py,\n", "line 2: expected a file and")]:
        path.write_text(text)
        with pytest.raises(MimicsError, match=expected):
            read_students(path)
    with pytest.raises(MimicsError, match="does not exist"):
        read_students(tmp_path / "nothing.csv")
