"""The teacher's kit end to end: a class's files through its battery, grade.py and the
course's workflow (reasons, feedback files, late submissions, hidden seeds, the
leaderboard, the class list).

The students: a good one (the reciprocal_avoidance example), a copy of it with
comments added, a six-line "turn right when blocked" rule, one whose robots never
move, one whose step raises, one that returns NaN, one whose step never returns
on the crossroads, and one whose file has a syntax error. They go where the kit's
README says (``submissions/``), into the kit's own ``battery.toml`` (only its list
of files, its seeds and its time-out changed), through ``mimics battery run`` and
``mimics battery report --grade grade.py``. Each mark must be what the kit's rule
gives, recomputed from the runs' own summary.json files.
"""

from __future__ import annotations

import contextlib
import io
import json
import shutil
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd
import pytest

import mimics
from mimics.batteries.report import runs_table
from mimics.batteries.spec import load_battery
from mimics.interfaces.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
TIMEOUT = 20  # seconds of wall-clock time a run may take in the test's battery
LATE = "late<script>"  # a late submission whose name a web page must escape

STUDENTS = {
    "never_moves": "def step(robot):\n    return 0.0, robot.heading\n",
    "raises": "def step(robot):\n    x = 1\n    return robot.speed_to_goal()\n",
    "returns_nan": "def step(robot):\n    return float('nan'), robot.heading\n",
    "hangs": ("def step(robot):\n    if len(robot.comms) == 8:  # the crossroads only\n"
              "        while True:\n            pass\n    return 0.0, robot.heading\n"),
    "syntax": "def step(robot)\n    return 0.0, robot.heading\n",
    "turn_right": (  # the six-line rule: drive to the goal, turn right when blocked
        "import numpy as np\ndef step(robot):\n    x, y, _ = robot.pose\n"
        "    heading = np.arctan2(robot.goal[1] - y, robot.goal[0] - x)\n"
        "    blocked = (np.abs(robot.scan.angles) < 0.6) & (robot.scan.ranges < 1.2)\n"
        "    return (0.2, heading - 1.2) if blocked.any() else (0.5, heading)\n"),
}
CLASS_LIST = "file,student_id,name\ngood.py,s01,Good Student\nraises.py,s02,\nabsent.py,s99,Al\n"


@dataclass
class Marked:
    """The kit after its battery ran and was reported on, before and after a late file."""

    folder: Path
    status: int
    stderr: str
    report: int = 0
    marks: pd.DataFrame = field(default_factory=pd.DataFrame)
    feedback: dict[str, str] = field(default_factory=dict)
    board: pd.DataFrame = field(default_factory=pd.DataFrame)
    rows_before: list[dict] = field(default_factory=list)
    rows_after: list[dict] = field(default_factory=list)
    added: int = 0
    refused: tuple[int, str] = (0, "")
    marks_after: pd.DataFrame = field(default_factory=pd.DataFrame)
    page_after: str = ""


def _run_cli(args: list[str]) -> tuple[int, str]:
    stderr = io.StringIO()
    with contextlib.redirect_stderr(stderr):
        status = main(args)
    return status, stderr.getvalue()


def _rows(battery: Path) -> list[dict]:
    from mimics.batteries.store import BatteryStore

    store = BatteryStore.open(battery)
    try:
        return store.rows()
    finally:
        store.close()


@pytest.fixture(scope="module")
def kit(tmp_path_factory: pytest.TempPathFactory) -> Marked:
    """The kit with eight submissions run once into ``kit/class`` and reported on; then a
    late submission added and the class reported on again."""
    folder = tmp_path_factory.mktemp("kit") / "kit"
    shutil.copytree(EXAMPLES / "teaching_kit", folder)
    submissions = folder / "submissions"
    good = (EXAMPLES / "reciprocal_avoidance" / "algorithm.py").read_text()
    (submissions / "good.py").write_text(good)
    (submissions / "copy.py").write_text("# my own work\n\n" + good.replace("\n\n\n", "\n\n"))
    for name, code in STUDENTS.items():
        (submissions / f"{name}.py").write_text(code)
    names = ", ".join(f'"submissions/{name}.py"' for name in ["good", "copy", *STUDENTS])
    battery = (folder / "battery.toml").read_text()
    for old, new in [('algorithms = ["starter.py"]', f"algorithms = [{names}]"),
                     ("seeds = 3", "seeds = 1"), ("timeout = 120", f"timeout = {TIMEOUT}")]:
        assert old in battery
        battery = battery.replace(old, new)
    (folder / "battery.toml").write_text(battery)
    (folder / "students.csv").write_text(CLASS_LIST)
    # The good student reads the laser: compile its kernel here, before the battery,
    # so that the battery's time-out is spent on the students' code, never on a compile.
    mimics.simulate("circle_swap", str(EXAMPLES / "reciprocal_avoidance" / "algorithm.py"),
                    robots=2, time=0.2, seed=0)
    status, stderr = _run_cli(["battery", "run", str(folder / "battery.toml"), "--out",
                               str(folder / "class"), "--workers", "2", "--no-progress"])
    marked = Marked(folder, status, stderr)
    battery_folder = folder / "class"
    marked.report, _ = _run_cli(["battery", "report", str(battery_folder), "--no-runs",
                                 "--grade", str(folder / "grade.py")])
    marked.marks = pd.read_csv(battery_folder / "marks.csv", dtype={"student_id": str})
    marked.feedback = {p.stem: p.read_text() for p in (battery_folder / "feedback").glob("*.md")}
    marked.board = pd.read_csv(battery_folder / "leaderboard.csv", dtype={"student_id": str})
    marked.rows_before = _rows(battery_folder)

    (submissions / f"{LATE}.py").write_text((folder / "starter.py").read_text())
    marked.added, _ = _run_cli(["battery", "add", str(battery_folder),
                                str(submissions / f"{LATE}.py"), "--workers", "2",
                                "--no-progress"])
    marked.refused = _run_cli(["battery", "add", str(battery_folder),
                               str(submissions / "good.py")])
    marked.rows_after = _rows(battery_folder)
    _run_cli(["battery", "report", str(battery_folder), "--no-runs",
              "--grade", str(folder / "grade.py")])
    marked.marks_after = pd.read_csv(battery_folder / "marks.csv", dtype={"student_id": str})
    marked.page_after = (battery_folder / "leaderboard.html").read_text()
    return marked


def _marks_by_the_rule(runs: pd.DataFrame) -> dict[str, float]:
    """The kit's rule recomputed from each run's state and its own summary.json."""
    points: dict[str, list[float]] = {}
    for run in runs.itertuples():
        score = 0.0
        if run.state == "done":
            summary = json.loads((Path(run.folder) / "summary.json").read_text())
            fraction = summary["reached_goal"] / summary["robots"]
            score = (10.0 if summary["collisions"] == 0 else 6.0) * fraction
        points.setdefault(run.algorithm, []).append(score)
    return {name: round(sum(p) / len(p), 1) for name, p in points.items()}


def test_the_class_gets_the_marks_the_rule_gives(kit: Marked) -> None:
    # 4 students x 2 scenarios + the crossroads of `hangs` could not finish: exit status
    # 1, and only the time-out is worth a re-run (an exception repeats with the same seed)
    assert kit.status == 1, kit.stderr
    assert "7 of 16 runs could not finish (6 error, 1 timeout)" in kit.stderr, kit.stderr
    assert "--state timeout" in kit.stderr and "repeats with the same seed" in kit.stderr
    runs = runs_table(kit.folder / "class")
    runs = runs[runs["algorithm"] != LATE]  # added after the report (below)
    states = runs.groupby("algorithm")["state"].agg(set).to_dict()
    assert states == {"good": {"done"}, "copy": {"done"}, "turn_right": {"done"},
                      "never_moves": {"done"}, "raises": {"error"}, "returns_nan": {"error"},
                      "hangs": {"timeout", "done"}, "syntax": {"error"}}
    assert kit.report == 0
    marks = kit.marks.set_index("student")
    by_rule = _marks_by_the_rule(runs)
    assert marks["mark"].drop("absent").to_dict() == by_rule
    assert by_rule["good"] == by_rule["copy"] == 10.0
    assert by_rule["turn_right"] <= 6.0  # a trivial rule no longer scores 10/10
    assert by_rule["never_moves"] == by_rule["hangs"] == 0.0
    assert marks.loc["never_moves", "finished"] == 2  # ran to the end, safely, and scored 0


def test_every_mark_has_its_reason(kit: Marked) -> None:
    reasons = kit.marks.set_index("student")["reason"].to_dict()
    assert reasons["good"] == "20 of 20 robots home without collision on 2 of 2 runs"
    assert reasons["raises"].startswith(
        "raised AttributeError at submissions/raises.py:3 on seed 1 (crossroads); "
        "2 of 2 runs failed")
    assert reasons["hangs"].startswith(
        f"stopped: step did not return within {TIMEOUT} s (submissions/hangs.py:3) on seed 1 "
        "(crossroads); 1 of 2 runs failed; 0 of 12 robots home")
    assert reasons["syntax"] == "file did not load: SyntaxError at line 1 (expected ':')"
    assert reasons["never_moves"] == ("0 of 20 robots home without collision on 2 of 2 runs, "
                                      "20 removed as deadlocked (no progress)")
    assert reasons["returns_nan"].startswith(
        "step returned a non-finite reference (speed_ref=nan) at submissions/returns_nan.py:2 "
        "on seed 1 (crossroads)")
    assert reasons["absent"] == "no submission"


def test_each_student_gets_a_feedback_file(kit: Marked) -> None:
    # keyed by the class list's ids where it has a row, else by the file's name
    assert set(kit.feedback) == {"s01", "copy", "turn_right", "never_moves", "s02",
                                 "returns_nan", "hangs", "syntax", "s99"}
    good = kit.feedback["s01"]
    assert good.startswith("# Feedback for s01 (Good Student)") and "- Mark: 10" in good
    assert "| crossroads | per_arm=2 | 1 | " in good and "| circle_swap | robots=12 | 1 | " in good
    assert "First error" not in good
    raises = kit.feedback["s02"]
    assert "- Mark: 0" in raises and "## First error" in raises
    assert "submissions/raises.py, line 3:" in raises
    assert "3 | return robot.speed_to_goal()" in raises
    hangs = kit.feedback["hangs"]
    assert "stopped: time-out" in hangs and "3 | while True:" in hangs
    assert "1 | def step(robot)" in kit.feedback["syntax"]
    assert "no submission" in kit.feedback["s99"] and "s99 (Al)" in kit.feedback["s99"]


def test_the_class_list_keys_the_marks(kit: Marked) -> None:
    marks = kit.marks.set_index("student")
    assert marks.loc["good", ["student_id", "name"]].tolist() == ["s01", "Good Student"]
    assert marks.loc["raises", "student_id"] == "s02"
    assert marks.loc["turn_right", "student_id"] == "turn_right"  # no row: the file's name
    assert marks.loc["absent", ["student_id", "mark"]].tolist() == ["s99", 0.0]


def test_a_copied_submission_is_flagged(kit: Marked) -> None:
    copies = kit.marks.set_index("student")["copy_of"].fillna("").to_dict()
    assert copies["copy"] == "good" and copies["good"] == "copy"
    assert copies["turn_right"] == "" and copies["never_moves"] == ""


def test_the_leaderboard_ranks_by_mark_then_time(kit: Marked) -> None:
    board = kit.board
    assert board["student_id"].tolist()[:2] in (["s01", "copy"], ["copy", "s01"])
    key = list(zip(-board["mark"], board["time_to_goal"].fillna(float("inf")), strict=True))
    assert key == sorted(key)
    assert (board["rank"].diff().dropna() >= 0).all()
    marks = kit.marks.set_index("student_id")
    assert board.set_index("student_id")["mark"].to_dict() == marks["mark"].to_dict()


def test_a_late_submission_runs_alone_and_joins_the_marks(kit: Marked) -> None:
    assert kit.added == 1  # as `resume`: the battery still holds the others' failed runs
    before = {row["id"]: row for row in kit.rows_before}
    after = {row["id"]: row for row in kit.rows_after}
    assert {k: after[k] for k in before} == before  # the others' runs untouched
    new = [row for k, row in after.items() if k not in before]
    assert sorted((r["algorithm"], r["scenario"], r["seed"]) for r in new) == [
        (LATE, "circle_swap", 1), (LATE, "crossroads", 1)]
    assert all(r["state"] == "done" for r in new)
    assert kit.refused[0] == 2 and "already has good" in kit.refused[1]
    assert "--replace" in kit.refused[1] and len(kit.refused[1].strip().splitlines()) == 1
    assert LATE in kit.marks_after["student"].tolist()
    assert "late&lt;script&gt;" in kit.page_after and "<script" not in kit.page_after


def test_a_resubmission_replaces_only_its_own_runs(kit: Marked, tmp_path: Path) -> None:
    battery = tmp_path / "class"
    shutil.copytree(kit.folder / "class", battery)
    rows = {r["id"]: r for r in _rows(battery)}
    (kit.folder / "submissions" / "syntax.py").write_text(STUDENTS["never_moves"])
    status, _ = _run_cli(["battery", "add", str(battery),
                          str(kit.folder / "submissions" / "syntax.py"), "--replace",
                          "--workers", "2", "--no-progress"])
    assert status == 1  # the others' failed runs are still there
    after = {r["id"]: r for r in _rows(battery)}
    kept = {k: r for k, r in rows.items() if r["algorithm"] != "syntax"}
    assert {k: after[k] for k in kept} == kept
    assert sorted(r["state"] for r in after.values() if r["algorithm"] == "syntax") == [
        "done", "done"]
    assert len(after) == len(rows)


def test_bad_input_to_battery_add_is_one_line_and_status_2(kit: Marked) -> None:
    battery = kit.folder / "class"
    rows = _rows(battery)
    good = str(kit.folder / "submissions" / "good.py")
    for args, expected in [
            ([str(kit.folder / "ASSIGNMENT.md")], "expected a .py file"),
            ([str(kit.folder / "submissions" / "nobody.py")], "no such file"),
            ([good, str(kit.folder / "good.py")], "no such file"),
            ([str(kit.folder / "starter.py"), str(kit.folder / "starter.py")], "two files"),
            ([good], "already has good")]:
        status, error = _run_cli(["battery", "add", str(battery), *args])
        assert status == 2 and expected in error, error
        assert len(error.strip().splitlines()) == 1 and "Traceback" not in error
    status, error = _run_cli(["battery", "add", str(kit.folder / "nowhere"), good])
    assert status == 2 and "not a battery folder" in error
    assert _rows(battery) == rows  # nothing changed


def test_the_teacher_grades_on_hidden_seeds(kit: Marked, tmp_path: Path) -> None:
    kit_folder = EXAMPLES / "teaching_kit"
    hidden_file = kit_folder / "teacher" / "grading.toml"
    hidden = tomllib.loads(hidden_file.read_text())["battery"]["seeds"]
    assert set(hidden).isdisjoint({1, 2, 3}) and len(hidden) == 3
    student_spec, teacher_spec = (load_battery(kit_folder / "battery.toml"),
                                  load_battery(hidden_file))
    assert student_spec.seeds == (1, 2, 3)
    assert teacher_spec.scenarios == student_spec.scenarios  # the same scenarios, parameters
    for setting in ("time", "timeout", "policy", "robot_logs", "record_every"):
        assert getattr(teacher_spec, setting) == getattr(student_spec, setting), setting
    status, stderr = _run_cli(["battery", "run", str(hidden_file), "--out",
                               str(tmp_path / "graded"), "--workers", "2", "--no-progress"])
    assert status == 0, stderr
    runs = runs_table(tmp_path / "graded")
    assert set(runs["seed"]) == set(hidden)
    assert "identical runs" not in stderr  # the seeds move the starts on both scenarios
    for _, cell in runs.groupby("scenario"):
        assert cell["digest"].nunique() == len(hidden)


def test_a_grading_file_without_usable_marks_is_one_line_and_status_2(
        kit: Marked, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad_grade.py"
    bad.write_text("def grade(runs):\n    return runs.assign(mark='excellent')\n")
    assert main(["battery", "report", str(kit.folder / "class"), "--grade", str(bad)]) == 2
    error = capsys.readouterr().err
    assert "bad_grade.py" in error and "finite numbers" in error and "Traceback" not in error
