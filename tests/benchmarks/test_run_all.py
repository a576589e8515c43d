"""The benchmarks' one entry (``benchmarks/run_all.py``) names every benchmark, and no
tracked file names this machine's folders.

The benchmarks themselves never run here: ``--list`` reads their docstrings.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BENCHMARKS = ROOT / "benchmarks"
RUN_ALL = BENCHMARKS / "run_all.py"

#: Folders of this machine that a tracked file must not name (paths belong relative to
#: the repository: ``mimics/...``, ``../shared/data``).
MACHINE_PATHS = re.compile(r"/work/|/tmp/pytest|/root/")
#: Tracked files allowed to hold such a path, each with why.
ALLOWED = {
    "tests/benchmarks/test_run_all.py": "this test spells out the paths it looks for",
}


def run_all(*arguments: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(RUN_ALL), *arguments], cwd=ROOT,
                          capture_output=True, text=True, timeout=120)


def test_list_names_every_benchmark_with_what_it_measures() -> None:
    done = run_all("--list")
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    listed = {name: text.strip() for name, _, text in (line.partition(" ") for line in lines)}
    scripts = {path.stem for path in BENCHMARKS.glob("*.py")} - {"common", "run_all"}
    peers = {f"peers/{path.stem}" for path in (BENCHMARKS / "peers").glob("*.py")}
    assert set(listed) == scripts | peers
    assert len(lines) == len(listed)  # one line each
    assert {name for name, text in listed.items() if not text} == set()


def test_a_name_runs_that_benchmark_with_its_arguments() -> None:
    done = run_all("cave", "--help")  # argparse's help: the script's docstring, no run
    assert done.returncode == 0, done.stderr
    assert "Stage's Cave" in done.stdout and "--repeats" in done.stdout


def test_an_unknown_name_is_one_clear_error() -> None:
    done = run_all("no_such_benchmark")
    assert done.returncode == 2
    assert "no_such_benchmark" in done.stderr and "NAME" in done.stderr
    assert "cave" in done.stderr  # what was expected


def tracked_files() -> list[str]:
    try:
        done = subprocess.run(["git", "-C", str(ROOT), "ls-files", "-z"], capture_output=True,
                              timeout=60)
    except (OSError, subprocess.TimeoutExpired):
        pytest.skip("git is not available")
    if done.returncode != 0:
        pytest.skip("not a git checkout")
    return [name for name in done.stdout.decode().split("\0") if name]


def test_no_tracked_text_file_names_this_machines_folders() -> None:
    found: dict[str, str] = {}
    for name in tracked_files():
        path = ROOT / name
        if name in ALLOWED or not path.is_file():  # (a file being moved is gone a moment)
            continue
        data = path.read_bytes()
        if b"\0" in data[:8192]:  # binary
            continue
        hit = MACHINE_PATHS.search(data.decode("utf-8", errors="replace"))
        if hit:
            line = data[:hit.start()].count(b"\n") + 1
            found[name] = f"line {line}: {hit.group()}"
    assert found == {}


def test_each_allowed_file_exists() -> None:
    """An exception for a file that no longer exists is one to remove."""
    assert all((ROOT / name).is_file() for name in ALLOWED)


def test_the_pattern_catches_what_it_is_for() -> None:
    assert MACHINE_PATHS.search("Profile at /work/main/benchmarks/profile.py:50")
    assert MACHINE_PATHS.search("see /root/.cache/numba")
    assert MACHINE_PATHS.search("/tmp/pytest-of-root/pytest-3/test_x0/run")
    assert not MACHINE_PATHS.search("Profile at benchmarks/profile.py:50")
    assert not MACHINE_PATHS.search("MIMICS_DATA=../shared/data, out to runs/fig2")
