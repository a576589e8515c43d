"""The README's first command, run as written: the first thing a newcomer sees is a run
that ends well (issue 51)."""

from __future__ import annotations

import json
import re
import shlex
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def first_command() -> list[str]:
    """The ``mimics ...`` part of the README's first code block."""
    readme = (ROOT / "README.md").read_text()
    block = re.search(r"```\n(.*?)\n```", readme, re.S)
    assert block is not None
    command = block[1].split("&&")[-1].strip()
    assert command.startswith(".venv/bin/mimics run "), command
    return shlex.split(command.removeprefix(".venv/bin/"))


def test_the_first_command_completes_with_every_robot_arrived_and_no_collision(
        tmp_path: Path) -> None:
    words = first_command()
    done = subprocess.run([sys.executable, "-m", *words, "--out", str(tmp_path / "run"),
                           "--robot-logs", "off"], cwd=tmp_path, capture_output=True,
                          text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["status"] == "completed"
    assert summary["reached_goal"] == summary["robots"] >= 8
    assert summary["collisions"] == 0
    # what the README says of it
    readme = (ROOT / "README.md").read_text()
    assert f"{summary['robots']} of {summary['robots']}" in readme
    assert "0 collisions" in readme and "`completed`" in readme
