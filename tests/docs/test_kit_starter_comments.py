"""The teaching kit's starter says what ``robot.comms`` holds, and it holds that (issue 54:
the starter said "the others' rows" while every robot's row, its own included, is there)."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import mimics

ROOT = Path(__file__).resolve().parents[2]
STARTER = ROOT / "examples" / "teaching_kit" / "starter.py"


def comms_comment() -> str:
    """The starter's comment on ``robot.comms``, its lines joined."""
    lines = STARTER.read_text().splitlines()
    start = next(i for i, line in enumerate(lines) if "robot.comms " in line)
    found = [lines[start]]
    for line in lines[start + 1:]:  # its continuation lines: a comment with no name first
        if not re.match(r"^\s*#\s{10,}\S", line):
            break
        found.append(line)
    return " ".join(" ".join(line.strip().lstrip("#").split()) for line in found)


def test_every_robot_reads_every_robots_row_its_own_included() -> None:
    seen: list[tuple[int, list[int]]] = []

    def step(robot: Any) -> tuple[float, float]:
        seen.append((robot.id, sorted(int(i) for i in robot.comms[:, 0])))
        return 0.0, robot.pose[2]

    mimics.simulate("circle_swap", step, robots=4, time=0.3, seed=1)
    assert seen and all(ids == [0, 1, 2, 3] for _, ids in seen)
    assert {robot for robot, _ in seen} == {0, 1, 2, 3}


def test_the_starter_says_so() -> None:
    said = comms_comment()
    assert "[id, x, y, theta, v, w]" in said
    assert "every robot" in said and "own row included" in said, said
    assert "the others" not in said, said
