"""`mimics battery ...` through Typer's test runner: help, errors, the whole cycle."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pandas as pd
import pytest
from typer.testing import CliRunner

from mimics.interfaces.cli import battery_new as cli_battery_new
from mimics.interfaces.cli.battery import app

GOOD = '''
[battery]
algorithms = ["go_to_goal"]
seeds = 2
time = 1.0
timeout = 20
[[scenarios]]
name = "line"
robots = 2
'''


@pytest.fixture(autouse=True)
def config_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A private MIMICS_CONFIG_DIR for each test."""
    folder = tmp_path / "config"
    monkeypatch.setenv("MIMICS_CONFIG_DIR", str(folder))
    return folder


def invoke(*args: str, input: str | None = None) -> object:
    return CliRunner().invoke(app, [str(a) for a in args], input=input)


def refused_run(tmp_path: Path, text: str, *options: str) -> tuple[Path, str]:
    """``battery run`` of a battery file holding ``text``: the file and the one error line,
    after checking that it exits with status 2 and starts nothing."""
    path = tmp_path / "battery.toml"
    path.write_text(text)
    result = invoke("run", path, "--out", tmp_path / "out", *options)
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mimics: error: "), lines
    assert not (tmp_path / "out").exists()
    return path, lines[0]


def test_help_lists_the_commands() -> None:
    result = invoke("--help")
    assert result.exit_code == 0
    for command in ("new", "run", "status", "resume", "rerun-failed", "report", "compare"):
        assert command in result.output
    assert "--last" in invoke("run", "--help").output
    assert "--until" in invoke("run", "--help").output


@pytest.mark.parametrize(("text", "expected"), [
    ("[battery]\nalgorithms = [", "not valid TOML"),
    (GOOD.replace('"go_to_goal"', '"teleport"'), "unknown algorithm 'teleport'"),
    (GOOD.replace("robots = 2", "wheels = 4"), "scenario 'line' has no parameter 'wheels'"),
    (GOOD.replace("seeds = 2", "seeds = 2\nretries = 3"), "[battery]: unknown key 'retries'"),
])
def test_bad_battery_files_stop_before_anything_starts(tmp_path: Path, text: str,
                                                       expected: str) -> None:
    path, line = refused_run(tmp_path, text)
    assert expected in line and str(path) in line


def test_usage_errors_are_one_line(tmp_path: Path) -> None:
    for args, expected in ((("run",), "give a battery file"),
                           (("run", "--last"), "no battery saved yet"),
                           (("status", tmp_path), "not a battery folder"),
                           (("resume", tmp_path), "not a battery folder"),
                           (("report", tmp_path), "not a battery folder"),
                           (("new", "--no-input"), "no algorithm"),
                           (("new", "--no-input", "-a", "go_to_goal", "-s", "line", "-p",
                             "wheels=4"), "no chosen scenario has a parameter 'wheels'")):
        result = invoke(*args)
        assert result.exit_code == 2, args
        assert result.stderr.startswith("mimics: error: ") and expected in result.stderr, args


def test_new_run_last_status_report_resume(tmp_path: Path) -> None:
    saved = tmp_path / "sets" / "night.toml"
    result = invoke("new", "--no-input", "-o", saved, "-a", "go_to_goal", "-s", "line",
                    "-p", "robots=1,2", "--seeds", "2", "--time", "1", "--timeout", "20")
    assert result.exit_code == 0, result.output
    assert "4 runs" in result.output
    data = tomllib.loads(saved.read_text())
    assert data["scenarios"] == [{"name": "line", "robots": [1, 2]}]
    assert data["battery"]["seeds"] == 2
    assert invoke("new", "--no-input", "-o", saved, "-a", "go_to_goal", "-s",
                  "line").exit_code == 2  # exists: --force needed

    out = tmp_path / "night1"
    result = invoke("run", "--last", "--out", out, "--workers", "1", "--no-progress")
    assert result.exit_code == 0, result.output + result.stderr
    assert "4 runs: 4 done" in result.output
    assert (out / "battery.toml").read_text() == saved.read_text()

    status = invoke("status", out)
    assert status.exit_code == 0
    assert "done" in status.output and "no" in status.output

    csv, parquet = tmp_path / "t.csv", tmp_path / "t.parquet"
    report = invoke("report", out, "--csv", csv, "--parquet", parquet)
    assert report.exit_code == 0, report.output
    assert "go_to_goal" in report.output and "robots=2" in report.output
    table = pd.read_csv(csv)
    assert len(table) == 4 and set(table["state"]) == {"done"}
    assert list(table["param_robots"]) == [1, 1, 2, 2]
    assert pd.read_parquet(parquet)["seed"].tolist() == [1, 2, 1, 2]

    assert invoke("resume", out, "--no-progress").exit_code == 0
    assert invoke("rerun-failed", out, "--no-progress").exit_code == 0
    assert invoke("run", saved, "--out", out).exit_code == 2  # already a battery


def test_new_asks_for_what_the_options_do_not_give(tmp_path: Path,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(cli_battery_new, "stdin_is_terminal", lambda: True)
    algorithms = [name for name, _ in __import__("mimics.catalog").catalog.list_algorithms()]
    number = algorithms.index("go_to_goal") + 1
    # (the empty answer: no stopping rule, a fixed number of seeds)
    answers = "\n".join([f"{number}", "line", "robots=1,3", "", "5", "2.5", "60", "deactivate"])
    path = tmp_path / "b.toml"
    result = invoke("new", "-o", path, input=answers + "\n")
    assert result.exit_code == 0, result.output
    data = tomllib.loads(path.read_text())
    assert data["battery"] == {"algorithms": ["go_to_goal"], "seeds": 5, "time": 2.5,
                               "timeout": 60.0, "policy": "deactivate", "robot_logs": "off"}
    assert data["scenarios"] == [{"name": "line", "robots": [1, 3]}]


def test_new_writes_a_stopping_rule_that_runs(tmp_path: Path) -> None:
    """--until gives the file a [battery.until] table in place of its seeds; the battery
    file runs, its cells stopping at max_seeds here (2 seeds, a target none can meet)."""
    saved = tmp_path / "rule.toml"
    result = invoke("new", "--no-input", "-o", saved, "-a", "go_to_goal", "-s", "line",
                    "-p", "robots=1", "--until", "path_length:0.000001", "--min-seeds", "2",
                    "--max-seeds", "2", "--time", "1", "--timeout", "20")
    assert result.exit_code == 0, result.output + result.stderr
    assert "2 runs in the first round" in result.output and "path_length" in result.output
    data = tomllib.loads(saved.read_text())
    assert "seeds" not in data["battery"]
    assert data["battery"]["until"] == {"metric": "path_length", "half_width": 1e-06,
                                        "min_seeds": 2, "max_seeds": 2}
    out = tmp_path / "rule1"
    result = invoke("run", "--last", "--out", out, "--workers", "1", "--no-progress")
    assert result.exit_code == 0, result.output + result.stderr
    assert "2 runs: 2 done" in result.output
    # the defaults of the bounds: those of a [battery.until] table without them
    invoke("new", "--no-input", "-o", saved, "--force", "-a", "go_to_goal", "-s", "line",
           "--until", "time_to_goal:0.5")
    assert tomllib.loads(saved.read_text())["battery"]["until"] == {
        "metric": "time_to_goal", "half_width": 0.5, "min_seeds": 20, "max_seeds": 500}


def test_new_offers_the_stopping_rule_when_asking(tmp_path: Path,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(cli_battery_new, "stdin_is_terminal", lambda: True)
    answers = "\n".join(["go_to_goal", "line", "", "success:0.1", "20", "200", "", "", ""])
    path = tmp_path / "asked.toml"
    result = invoke("new", "-o", path, input=answers + "\n")
    assert result.exit_code == 0, result.output
    assert "Stop each cell when its answer is known?" in result.output
    battery = tomllib.loads(path.read_text())["battery"]
    assert battery["until"] == {"metric": "success", "half_width": 0.1, "min_seeds": 20,
                                "max_seeds": 200}
    assert "seeds" not in battery and battery["timeout"] == 300.0


@pytest.mark.parametrize(("options", "expected"), [
    (("--seeds", "5", "--until", "success:0.1"), "--seeds: not with --until"),
    (("--min-seeds", "5",), "--min-seeds: only with --until"),
    (("--until", "speed:0.1"), "--until metric: expected one of"),
    (("--until", "success:-1"), "--until half_width: expected a positive number"),
    (("--until", "success:0.1", "--min-seeds", "40", "--max-seeds", "20"),
     "--min-seeds: 40 is more than max_seeds 20"),
    (("--until", "success:0.1", "--max-seeds", "1"), "--max-seeds: expected a whole number"),
])
def test_new_refuses_a_bad_stopping_rule_in_one_line(tmp_path: Path, options: tuple[str, ...],
                                                     expected: str) -> None:
    path = tmp_path / "bad.toml"
    result = invoke("new", "--no-input", "-o", path, "-a", "go_to_goal", "-s", "line", *options)
    assert result.exit_code == 2
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mimics: error: ") and expected in lines[0]
    assert not path.exists()


UNTIL = GOOD.replace("seeds = 2\n", "") + '''
[battery.until]
metric = "time_to_goal"
half_width = 0.2
'''


@pytest.mark.parametrize(("text", "expected"), [
    (UNTIL.replace('"time_to_goal"', '"speed"'), "[battery.until] metric: expected one of"),
    (UNTIL.replace("0.2", "0"), "[battery.until] half_width: expected a positive number"),
    (UNTIL.replace("0.2", "-0.5"), "[battery.until] half_width: expected a positive number"),
    (UNTIL.replace("0.2", '"narrow"'), "[battery.until] half_width: expected a positive"),
    (UNTIL + "min_seeds = 50\nmax_seeds = 20\n", "[battery.until] min_seeds: 50 is more than"),
    (UNTIL + "max_seeds = 1.5\n", "[battery.until] max_seeds: expected a whole number"),
    (UNTIL.replace("[battery]", "[battery]\nseeds = 3"), "[battery] seeds: not with"),
])
def test_bad_until_tables_exit_2_naming_the_field(tmp_path: Path, text: str,
                                                  expected: str) -> None:
    path, line = refused_run(tmp_path, text)
    assert expected in line and str(path) in line


@pytest.mark.parametrize(("option", "expected"), [
    ("speed:0.2", "--until metric: expected one of"),
    ("time_to_goal:0", "--until half_width: expected a positive number"),
    ("time_to_goal:wide", "--until 'time_to_goal:wide': the half-width 'wide' is not a number"),
    ("time_to_goal", "--until 'time_to_goal': expected METRIC:HALF_WIDTH"),
])
def test_bad_until_options_exit_2(tmp_path: Path, option: str, expected: str) -> None:
    _, line = refused_run(tmp_path, GOOD, "--until", option)
    assert expected in line, line


def test_until_option_runs_seeds_in_rounds_and_status_shows_them(tmp_path: Path) -> None:
    from tests.batteries.helpers import fault

    path = tmp_path / "battery.toml"
    # the file's [battery.until] bounds the seeds (20 to 24); --until names metric and target
    bounded = GOOD.replace("seeds = 2\n", "").replace("[[scenarios]]", (
        '[battery.until]\nmetric = "success"\nhalf_width = 0.4\nmin_seeds = 20\n'
        "max_seeds = 24\n[[scenarios]]"))
    path.write_text(bounded.replace('"go_to_goal"', f'"{fault("stand_still")}"')
                    + "random_yaw = false\n")
    out = tmp_path / "out"
    result = invoke("run", path, "--out", out, "--until", "path_length:0.5", "--workers", "1",
                    "--no-progress")
    assert result.exit_code == 0, result.output + result.stderr
    # robots standing still: no spread, on which the rule never stops: 20 seeds, then
    # max_seeds, and the cell is named short of its target
    assert "24 runs: 24 done" in result.output
    assert "seeds 1-24 of stand_still x line (robots=2, random_yaw=False) gave identical" \
        in result.stderr
    status = invoke("status", out)
    assert status.exit_code == 0
    assert "until the 95% interval of path_length is within ± 0.5" in status.output
    assert "max seeds" in status.output
