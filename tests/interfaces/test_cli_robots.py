"""`mimics robot show` and `mimics list robots` through Typer's test runner."""

from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread
from typer.testing import CliRunner

from mimics.interfaces.cli.program import app
from mimics.world.robot_types import BUILTIN_ROBOT_TYPES

runner = CliRunner()


def test_list_robots_names_every_builtin_type() -> None:
    result = runner.invoke(app, ["list", "robots"], terminal_width=200)
    assert result.exit_code == 0, result.output
    for name in BUILTIN_ROBOT_TYPES:
        assert name in result.output
    assert "LDS-01" in result.output


def test_show_prints_the_parameters_and_writes_the_figure(tmp_path: Path) -> None:
    out = tmp_path / "p3at.png"
    result = runner.invoke(app, ["robot", "show", "Pioneer3AT", "--out", str(out)],
                           terminal_width=200)
    assert result.exit_code == 0, result.output
    assert "1.489, 3.297, 0" in result.output  # the tuned speed gains
    assert "speed step to 0.5 m/s" in result.output
    assert "settles (2%) in 1.0 s, overshoot 0.0%" in result.output
    assert "settles (2 deg) in 1.9 s" in result.output
    # the datasheet noise and where it comes from
    assert "sigma 0.03 m" in result.output and "Hokuyo UTM-30LX specifications" in result.output
    assert "odom_error" in result.output
    image = imread(out)
    assert image.shape[:2] == (450, 1500)
    assert np.ptp(image[..., :3]) > 0.5  # something is drawn


def test_show_writes_robot_type_png_by_default(tmp_path: Path,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    result = runner.invoke(app, ["robot", "show", "point"])
    assert result.exit_code == 0, result.output
    assert (tmp_path / "robot_point.png").is_file()


def test_unknown_type_is_one_line_listing_the_known_names(tmp_path: Path) -> None:
    result = runner.invoke(app, ["robot", "show", "Roomba"], terminal_width=300)
    assert result.exit_code == 2
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("mimics: error: unknown robot type 'Roomba'")
    for name in BUILTIN_ROBOT_TYPES:
        assert name in lines[0]


def test_unwritable_figure_is_one_line(tmp_path: Path) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("")
    result = runner.invoke(app, ["robot", "show", "e-puck", "--out", str(blocker / "x.png")])
    assert result.exit_code == 2
    assert result.output.strip().splitlines()[-1].startswith("mimics: error: cannot write")


def test_list_scenarios_says_what_the_seed_changes() -> None:
    result = runner.invoke(app, ["list", "scenarios"], terminal_width=250)
    assert result.exit_code == 0, result.output
    assert "the seed changes" in result.output
    assert "each robot's start heading" in result.output  # the line
    assert "start jitter" in result.output  # circle_swap, corridor, cave, hospital
