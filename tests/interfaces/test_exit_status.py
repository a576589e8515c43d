"""Exit statuses mean something: 0 done as asked, 1 ran but failed, 2 bad input."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest

import mimics.records.runner as runner
from mimics.interfaces.cli import main

RAISING = "def step(robot):\n    if robot.time > 0.25:\n        raise ValueError('boom')\n" \
          "    return 0.5, 0.0\n"
PAIR = ('map = { segments = [], bounds = [0.0, 0.0, 10.0, 6.0] }\n'
        '[[robots]]\ntype = "Pioneer2DX"\nx = 2.0\ny = 2.0\ngoal = [8.0, 2.0]\n'
        '[[robots]]\ntype = "Pioneer2DX"\nx = 2.1\ny = 2.0\ngoal = [8.0, 4.0]\n'
        '[settings]\ntime_limit = 0.5\n')


def mimics(*argv: str) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main([str(a) for a in argv])
    return status, out.getvalue(), err.getvalue()


def test_the_root_help_gives_the_table() -> None:
    status, out, _ = mimics("--help")
    assert status == 0
    for line in ("Exit status (every command):", "0    done as asked", "1    it ran, but failed",
                 "2    bad input", "130  interrupted"):
        assert line in out


def test_run_exits_1_when_user_code_fails_under_abort_and_0_under_deactivate(
        tmp_path: Path) -> None:
    algorithm = tmp_path / "raising.py"
    algorithm.write_text(RAISING)
    status, out, _ = mimics("run", "line", algorithm, "--robots", "2", "--time", "1",
                            "--out", tmp_path / "abort")
    assert status == 1, out
    assert json.loads((tmp_path / "abort" / "summary.json").read_text())["status"] == "error"
    status, out, _ = mimics("run", "line", algorithm, "--robots", "2", "--time", "1",
                            "--policy", "deactivate", "--out", tmp_path / "deactivate")
    assert status == 0, out


def test_run_exits_0_at_the_time_limit_and_2_for_bad_input(tmp_path: Path) -> None:
    assert mimics("run", "line", "go_to_goal", "--robots", "2", "--time", "0.3", "--out",
                  tmp_path / "ok")[0] == 0
    status, _, err = mimics("run", "line", "go_to_goal", "--seed", "-1")
    assert status == 2 and err.count("\n") == 1 and "--seed" in err


def test_overlapping_starts_are_bad_input_unless_allowed(tmp_path: Path) -> None:
    scenario = tmp_path / "pair.toml"
    scenario.write_text(PAIR)
    status, _, err = mimics("run", scenario, "go_to_goal", "--out", tmp_path / "refused")
    assert status == 2
    assert "robots[0] (line 2) at (2, 2) and robots[1] (line 7) at (2.1, 2) overlap" in err
    assert not (tmp_path / "refused").exists()
    status, out, err = mimics("run", scenario, "go_to_goal", "--allow-overlap", "--out",
                              tmp_path / "kept")
    assert status == 0, out + err
    assert "kept on purpose (--allow-overlap): 1 start problem(s)" in err
    summary = json.loads((tmp_path / "kept" / "summary.json").read_text())
    assert summary["collisions"] == 2  # the engine sees the contact at time zero


@pytest.mark.parametrize(("error", "expected"), [
    (MemoryError(), "too large for this machine"),
    (OverflowError("cannot convert float infinity to integer"), "OverflowError"),
])
def test_the_last_resort_guard_turns_size_errors_into_one_line(
        monkeypatch: pytest.MonkeyPatch, error: Exception, expected: str) -> None:
    def boom(*args: object, **kwargs: object) -> None:
        raise error

    monkeypatch.setattr(runner, "prepare", boom)
    status, _, err = mimics("run", "line", "go_to_goal")
    assert status == 2 and expected in err and err.count("\n") == 1


def test_the_last_resort_guard_takes_numpy_value_errors_but_not_bugs(
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(runner, "prepare", lambda *a, **k: np.random.default_rng(-1))
    status, _, err = mimics("run", "line", "go_to_goal")
    assert status == 2 and "a value NumPy cannot use" in err

    def bug(*args: object, **kwargs: object) -> None:
        raise ValueError("a bug of ours")

    monkeypatch.setattr(runner, "prepare", bug)
    with pytest.raises(ValueError, match="a bug of ours"):
        mimics("run", "line", "go_to_goal")


def test_a_battery_exits_1_with_the_count_when_runs_could_not_finish(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MIMICS_CONFIG_DIR", str(tmp_path / "config"))
    (tmp_path / "raising.py").write_text(RAISING)
    battery = tmp_path / "battery.toml"
    battery.write_text('[battery]\nalgorithms = ["go_to_goal", "raising.py"]\nseeds = 1\n'
                       'time = 0.5\ntimeout = 60\n[[scenarios]]\nname = "line"\nrobots = 2\n')
    status, out, err = mimics("battery", "run", battery, "--out", tmp_path / "b", "--workers",
                              "1", "--no-progress")
    assert status == 1, out + err
    assert "mimics: 1 of 2 runs could not finish (1 error)" in err
    # an exception repeats with the same seed: re-running is not suggested for it
    assert "repeats with the same seed" in err and "rerun-failed" not in err


@pytest.mark.parametrize(("options", "named"), [
    (("--robots", "3", "--param", "robots=7"), "--robots 3 and --param robots=7"),
    (("--time", "2", "--param", "time_limit=5.0"), "--time 2 and --param time_limit=5.0"),
])
def test_two_values_for_one_parameter_are_bad_input_naming_both(
        tmp_path: Path, options: tuple[str, ...], named: str) -> None:
    status, _, err = mimics("run", "line", "go_to_goal", *options, "--out", tmp_path / "r")
    assert status == 2 and err.count("\n") == 1
    assert err.startswith(f"mimics: error: {named}: two values for the same parameter")
    assert not (tmp_path / "r").exists()
    # the same value twice is no conflict
    assert mimics("run", "line", "go_to_goal", "--robots", "2", "--param", "robots=2",
                  "--time", "0.3", "--out", tmp_path / "same")[0] == 0


def test_a_failing_step_is_reported_at_its_file_and_line(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    Path("my_algo.py").write_text("import math\n\n\ndef step(robot):\n    x, y, theta = "
                                  "robot.pose\n    gx, gy = robot.gaol\n    return 0.5, 0.0\n")
    status, out, _ = mimics("run", "line", "my_algo.py", "--robots", "2", "--out", "r")
    assert status == 1
    assert ("error: AttributeError in robot 0 at t=0 s, my_algo.py:6: 'Robot' object has no "
            "attribute 'gaol'\n    gx, gy = robot.gaol\n") in out
    summary = (tmp_path / "r" / "summary.txt").read_text()
    assert "my_algo.py:6: 'Robot' object has no attribute 'gaol'\n" in summary
    assert "\n" + " " * 24 + "gx, gy = robot.gaol\n" in summary  # indented under its value
