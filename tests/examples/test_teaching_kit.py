"""The teacher's kit end to end: a battery of two submissions, marked by its grade.py.

The good submission (the reciprocal_avoidance example) and the bad one (the
starter as handed out) run on the kit's scenarios; each mark printed and
written by ``mimics battery report --grade`` must equal the rule in the kit's
README, recomputed here from the runs' own summary.json files.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pandas as pd
import pytest

from mimics.interfaces.cli import main

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.fixture()
def kit(tmp_path: Path) -> Path:
    """The kit with two submissions, and its battery run once into ``kit/class``."""
    folder = tmp_path / "kit"
    shutil.copytree(EXAMPLES / "teaching_kit", folder)
    shutil.copy(EXAMPLES / "reciprocal_avoidance" / "algorithm.py", folder / "alice.py")
    shutil.copy(folder / "starter.py", folder / "bob.py")
    battery = (folder / "battery.toml").read_text()
    battery = battery.replace('algorithms = ["starter.py"]', 'algorithms = ["alice.py", "bob.py"]')
    (folder / "battery.toml").write_text(battery.replace("seeds = 3", "seeds = 1"))
    assert main(["battery", "run", str(folder / "battery.toml"), "--out", str(folder / "class"),
                 "--workers", "2", "--no-progress"]) == 0
    return folder


def _expected_marks(battery: Path) -> dict[str, float]:
    points: dict[str, list[float]] = {}
    for summary_file in battery.glob("runs/*/summary.json"):
        summary = json.loads(summary_file.read_text())
        student = summary["algorithm"]
        score = 6.0 * summary["reached_goal"] / summary["robots"]
        score += 4.0 * (summary["collisions"] == 0)
        points.setdefault(student, []).append(score)
    return {name: round(sum(p) / len(p), 1) for name, p in points.items()}


def test_a_good_and_a_bad_submission_get_the_marks_the_rule_gives(
        kit: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    battery = kit / "class"
    assert main(["battery", "report", str(battery), "--no-runs",
                 "--grade", str(kit / "grade.py")]) == 0
    printed = capsys.readouterr().out
    marks = pd.read_csv(battery / "marks.csv").set_index("student")
    assert marks.loc["alice", "mark"] == 10.0  # every robot home, no collision
    assert marks.loc["bob", "mark"] < 4.0  # straight lines: everyone collides
    assert marks["mark"].to_dict() == _expected_marks(battery)
    assert "alice" in printed and "marks.csv" in printed


    # a grading file that returns no usable marks: one line naming it, status 2
    bad = tmp_path / "bad_grade.py"
    bad.write_text("def grade(runs):\n    return runs.assign(mark='excellent')\n")
    assert main(["battery", "report", str(battery), "--grade", str(bad)]) == 2
    error = capsys.readouterr().err
    assert "bad_grade.py" in error and "finite numbers" in error and "Traceback" not in error
