"""The teacher's kit end to end: five students' files through its battery and grade.py.

The students: a good one (the reciprocal_avoidance example), one whose robots
never move, one whose step raises, one whose step returns NaN and one whose
step never returns. They go where the kit's README says (``submissions/``),
into the kit's own ``battery.toml`` (only its list of files, its seeds and its
time-out changed), through ``mimics battery run`` and ``mimics battery report
--grade grade.py``. Each mark must be what the kit's rule gives: 10 for all
robots home without a collision, 0 for each of the others (the hanging one is
stopped by the battery's ``timeout``), and equal to the rule recomputed from
the runs' own summary.json files.
"""

from __future__ import annotations

import contextlib
import io
import json
import shutil
from dataclasses import dataclass
from pathlib import Path

import pandas as pd
import pytest

import mimics
from mimics.batteries.report import runs_table
from mimics.interfaces.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
TIMEOUT = 20  # seconds of wall-clock time a run may take in the test's battery

STUDENTS = {
    "never_moves": "def step(robot):\n    return 0.0, robot.heading\n",
    "raises": "def step(robot):\n    return robot.speed_to_goal()\n",
    "returns_nan": "def step(robot):\n    return float('nan'), robot.heading\n",
    "hangs": "def step(robot):\n    while True:\n        pass\n",
}


@dataclass
class Marked:
    """The kit after its battery ran: its folder, and what ``battery run`` said."""

    folder: Path
    status: int
    stderr: str


@pytest.fixture(scope="module")
def kit(tmp_path_factory: pytest.TempPathFactory) -> Marked:
    """The kit with five submissions, and its battery run once into ``kit/class``."""
    folder = tmp_path_factory.mktemp("kit") / "kit"
    shutil.copytree(EXAMPLES / "teaching_kit", folder)
    submissions = folder / "submissions"
    shutil.copy(EXAMPLES / "reciprocal_avoidance" / "algorithm.py", submissions / "good.py")
    for name, code in STUDENTS.items():
        (submissions / f"{name}.py").write_text(code)
    names = ", ".join(f'"submissions/{name}.py"' for name in ["good", *STUDENTS])
    battery = (folder / "battery.toml").read_text()
    for old, new in [('algorithms = ["starter.py"]', f"algorithms = [{names}]"),
                     ("seeds = 3", "seeds = 1"), ("timeout = 120", f"timeout = {TIMEOUT}")]:
        assert old in battery
        battery = battery.replace(old, new)
    (folder / "battery.toml").write_text(battery)
    # The good student reads the laser: compile its kernel here, before the battery,
    # so that the battery's time-out is spent on the students' code, never on a compile.
    mimics.simulate("circle_swap", str(EXAMPLES / "reciprocal_avoidance" / "algorithm.py"),
                    robots=2, time=0.2, seed=0)
    stderr = io.StringIO()
    with contextlib.redirect_stderr(stderr):
        status = main(["battery", "run", str(folder / "battery.toml"), "--out",
                       str(folder / "class"), "--workers", "2", "--no-progress"])
    return Marked(folder, status, stderr.getvalue())


def _marks_by_the_rule(battery: Path) -> dict[str, float]:
    """The kit's rule recomputed from each run's state and its own summary.json."""
    points: dict[str, list[float]] = {}
    for run in runs_table(battery).itertuples():
        score = 0.0
        if run.state == "done":
            summary = json.loads((Path(run.folder) / "summary.json").read_text())
            fraction = summary["reached_goal"] / summary["robots"]
            score = (10.0 if summary["collisions"] == 0 else 6.0) * fraction
        points.setdefault(run.algorithm, []).append(score)
    return {name: round(sum(p) / len(p), 1) for name, p in points.items()}


def test_five_students_get_the_marks_the_rule_gives(
        kit: Marked, capsys: pytest.CaptureFixture[str]) -> None:
    # 3 students x 2 scenarios could not finish: exit status 1, and only the
    # time-outs are worth a re-run (an exception repeats with the same seed)
    assert kit.status == 1, kit.stderr
    assert "6 of 10 runs could not finish (4 error, 2 timeout)" in kit.stderr, kit.stderr
    assert "--state timeout" in kit.stderr and "repeats with the same seed" in kit.stderr
    states = runs_table(kit.folder / "class").groupby("algorithm")["state"].agg(set).to_dict()
    assert states == {"good": {"done"}, "never_moves": {"done"}, "raises": {"error"},
                      "returns_nan": {"error"}, "hangs": {"timeout"}}

    battery = kit.folder / "class"
    assert main(["battery", "report", str(battery), "--no-runs",
                 "--grade", str(kit.folder / "grade.py")]) == 0
    printed = capsys.readouterr().out
    marks = pd.read_csv(battery / "marks.csv").set_index("student")
    assert marks["mark"].to_dict() == {"good": 10.0, "never_moves": 0.0, "raises": 0.0,
                                       "returns_nan": 0.0, "hangs": 0.0}
    assert marks["mark"].to_dict() == _marks_by_the_rule(battery)
    assert marks.loc["never_moves", "finished"] == 2  # ran to the end, safely, and scored 0
    assert "good" in printed and "marks.csv" in printed


def test_a_grading_file_without_usable_marks_is_one_line_and_status_2(
        kit: Marked, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "bad_grade.py"
    bad.write_text("def grade(runs):\n    return runs.assign(mark='excellent')\n")
    assert main(["battery", "report", str(kit.folder / "class"), "--grade", str(bad)]) == 2
    error = capsys.readouterr().err
    assert "bad_grade.py" in error and "finite numbers" in error and "Traceback" not in error
