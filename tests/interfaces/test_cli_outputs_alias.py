"""Outputs that alias an input or each other are refused before anything is written.

Every command that reads a run folder, a battery folder, a map or a scenario and
writes a file is pointed at its own inputs (directly, through ``..``, a symbolic
link and a hard link) and at one file for two outputs: each must exit 2 with one
line naming the option, and every input must survive byte for byte.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from mimics.interfaces.cli import main
from tests.fuzzing import BATTERY_TOML, copy_tree, make_run_folder, map_files, snapshot


@pytest.fixture(scope="module")
def made(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from mimics.batteries.spec import load_battery
    from mimics.batteries.store import BatteryStore

    root = tmp_path_factory.mktemp("alias")
    make_run_folder(root / "run")
    (root / "battery.toml").write_text(BATTERY_TOML)
    BatteryStore.create(root / "battery", load_battery(root / "battery.toml")).close()
    map_files(root / "maps")
    return root


@pytest.fixture()
def work(made: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A fresh copy of the inputs, as the current folder."""
    copy_tree(made, tmp_path / "w")
    monkeypatch.chdir(tmp_path / "w")
    monkeypatch.setenv("MIMICS_CONFIG_DIR", str(tmp_path / "config"))
    return tmp_path / "w"


def refused(capsys: pytest.CaptureFixture[str], argv: list[str], option: str) -> str:
    """Run ``mimics ARGV``: exit 2, one error line naming ``option``."""
    assert main(argv) == 2, argv
    lines = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("mimics: error: "), lines
    assert option in lines[0], lines[0]
    return lines[0]


EXPORT_ALIASES = [
    ["--mcap", "run/trajectory.parquet"],
    ["--bag", "run/summary.json"],
    ["--mcap", "run/../run/events.parquet"],
    ["--mcap", "run/robots/robot_0000.log"],
    ["--bag", "run/new.bag"],  # a new file in the run folder: the folder holds records only
    ["--mcap", "run"],
]


@pytest.mark.parametrize("options", EXPORT_ALIASES, ids=[" ".join(o) for o in EXPORT_ALIASES])
def test_export_never_writes_into_the_run_it_reads(
        work: Path, capsys: pytest.CaptureFixture[str], options: list[str]) -> None:
    before = snapshot(work)
    refused(capsys, ["export", "run", *options], options[0])
    assert snapshot(work) == before  # the run folder survives byte for byte


def test_export_refuses_one_file_for_both_outputs_and_links_into_the_run(
        work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    before = snapshot(work)
    line = refused(capsys, ["export", "run", "--mcap", "x.out", "--bag", "./x.out"], "--mcap")
    assert "--bag" in line
    assert not (work / "x.out").exists()
    os.symlink(work / "run" / "summary.json", work / "soft.json")
    os.link(work / "run" / "trajectory.parquet", work / "hard.parquet")
    refused(capsys, ["export", "run", "--bag", "soft.json"], "--bag")
    refused(capsys, ["export", "run", "--mcap", "hard.parquet"], "--mcap")
    after = snapshot(work)
    after.pop("hard.parquet")  # the hard link made above (a symlink is not in a snapshot)
    assert after == before


def test_an_export_beside_the_run_is_still_written(work: Path) -> None:
    assert main(["export", "run", "--mcap", "run.mcap"]) == 0
    assert (work / "run.mcap").stat().st_size > 0


@pytest.mark.parametrize("argv", [
    ["plot", "run", "--out", "run/summary.json"],
    ["plot", "run", "--out", "run/trajectory.parquet"],
    ["replay", "run", "--gif", "run/robots/x.gif"],
    ["logs", "export", "run", "--out", "run/summary.json"],
    ["logs", "export", "run", "--out", "run/trajectory.parquet"],
    ["battery", "report", "battery", "--csv", "battery/battery.db"],
    ["battery", "report", "battery", "--parquet", "battery/runs/x.parquet"],
    ["battery", "report", "battery", "--csv", "t.csv", "--parquet", "t.csv"],
    ["battery", "compare", "battery", "--csv", "battery/battery.toml"],
    ["battery", "plot", "battery", "--out", "battery/runs"],
    ["map", "import", "maps/room.toml", "--out", "maps/room.toml"],
    ["map", "import", "maps/room.json", "--out", "maps/../maps/room.json"],
    ["map", "show", "maps/plan.svg", "--out", "maps/plan.svg"],
    ["run", "run/scenario.toml", "go_to_goal", "--out", "run"],
    ["run", "battery.toml", "go_to_goal", "--out", "battery.toml"],
    ["ros", "run/scenario.toml", "--out", "run"],  # refused before a ROS master is needed
    ["battery", "new", "-a", "go_to_goal", "-s", "line", "--no-input", "--force",
     "-o", "run/summary.json"],
    ["battery", "new", "-a", "go_to_goal", "-s", "line", "--no-input", "--force",
     "-o", "battery/battery.toml"],
], ids=lambda argv: " ".join(argv))
def test_every_output_over_an_input_is_refused_before_anything_is_written(
        work: Path, capsys: pytest.CaptureFixture[str], argv: list[str]) -> None:
    before = snapshot(work)
    option = next(token for token in reversed(argv) if token.startswith("-")
                  and token not in ("--no-input", "--force"))
    refused(capsys, argv, option)
    assert snapshot(work) == before


def test_the_default_places_inside_a_run_stay_allowed(work: Path) -> None:
    assert main(["plot", "run"]) == 0  # RUN/run.png, the documented default
    assert (work / "run" / "run.png").is_file()
    assert main(["logs", "export", "run", "--out", "run/robots"]) == 0  # the logs' own folder
    assert main(["battery", "report", "battery", "--csv", "battery/table.csv"]) == 0


def test_battery_new_refuses_the_algorithm_file_it_names(
        work: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (work / "algo.py").write_text("def step(robot):\n    return 0.0, 0.0\n")
    before = snapshot(work)
    refused(capsys, ["battery", "new", "-a", "algo.py", "-s", "line", "--no-input", "--force",
                     "-o", "algo.py"], "--output")
    assert snapshot(work) == before
