"""The command line with C and C++ algorithms: runs, compile errors, crashes, include-dir."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from mimics.interfaces.cli import main
from tests.native.conftest import ALGORITHMS, EXAMPLES


def test_include_dir_prints_the_folder_of_the_header(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["include-dir"]) == 0
    folder = Path(capsys.readouterr().out.strip())
    assert (folder / "mimics.h").is_file()
    assert "#define MIMICS_ABI_VERSION 1" in (folder / "mimics.h").read_text()


def test_run_takes_a_c_file_as_it_is(tmp_path: Path, capfd: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "run"
    # facing their goals: go_to_goal drives straight, and random headings make it clip
    # a neighbour while it turns
    code = main(["run", "line", str(EXAMPLES / "c" / "go_to_goal.c"), "--robots", "10",
                 "--param", "random_yaw=false", "--out", str(out), "--robot-logs", "off"])
    captured = capfd.readouterr()
    assert code == 0, captured.err
    summary = json.loads((out / "summary.json").read_text())
    assert (summary["algorithm"], summary["robots"], summary["reached_goal"]) == (
        "go_to_goal.c", 10, 10)
    assert "go_to_goal.c" in captured.out and "records in" in captured.out  # the child's summary


def test_a_compile_error_is_one_line_with_file_and_line_and_status_2(
        tmp_path: Path, capfd: pytest.CaptureFixture[str]) -> None:
    source = ALGORITHMS / "syntax_error.c"
    code = main(["run", "line", str(source), "--out", str(tmp_path / "run")])
    captured = capfd.readouterr()
    assert code == 2
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith(f"mimics: error: {source}:7:5: error: ")
    assert "undeclared_name" in lines[0]


def test_a_crash_in_run_is_one_line_naming_the_signal_and_status_1(
        tmp_path: Path, capfd: pytest.CaptureFixture[str]) -> None:
    source = ALGORITHMS / "crash.c"
    code = main(["run", "line", str(source), "--robots", "3", "--out", str(tmp_path / "run")])
    captured = capfd.readouterr()
    assert code == 1
    assert captured.err.strip() == (f"mimics: error: {source} crashed the simulation in robot "
                                    "1's call at step 3: killed by SIGSEGV (Segmentation fault)")
    assert "Traceback" not in captured.out + captured.err
    assert "core dumped" not in captured.out + captured.err
