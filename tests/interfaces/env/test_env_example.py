"""examples/rl_loop runs, and its scripted policy earns the return the reward's sum predicts."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

SCRIPT = Path(__file__).parents[3] / "examples" / "rl_loop" / "run.py"
LINE = re.compile(r"episode (\d+): mean return (-?[\d.]+) over (\d+) agents; (.*)")


def _run(*args: str) -> list[re.Match]:
    # one numba thread: see conftest.py
    done = subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True,
                          check=True, env={**os.environ, "NUMBA_NUM_THREADS": "1"})
    return [LINE.fullmatch(line) for line in done.stdout.strip().splitlines()]


def test_scripted_policy_brings_every_robot_to_its_goal() -> None:
    lines = _run("--episodes", "1")
    assert len(lines) == 1 and lines[0] is not None
    # the progress rewards add up to 8 m (the circle's diameter) minus the last
    # distance, within the 0.2 m goal tolerance, and each goal pays 10
    assert 17.8 <= float(lines[0][2]) <= 18.0
    assert lines[0][3] == "8" and lines[0][4] == "reached_goal 8"


def test_random_policy_runs_its_episodes() -> None:
    lines = _run("--policy", "random", "--episodes", "2", "--robots", "4", "--time", "10")
    assert [m[1] for m in lines] == ["0", "1"]
    assert all(m[3] == "4" for m in lines)
