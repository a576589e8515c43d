"""The occupancy grid against shapely, and `mimics export`'s one-line errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, box

import mimics
from mimics.interfaces.cli import main
from mimics.interfaces.rosexport.grid import grid_shape, rasterise
from mimics.world.maps import Map

BOUNDS = (-1.0, -2.0, 3.0, 1.0)
RESOLUTION = 0.25
coordinate = st.floats(-1.5, 3.5, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(coordinate, coordinate, coordinate, coordinate), min_size=1,
                max_size=3))
def test_grid_marks_every_cell_a_wall_crosses_and_no_cell_it_misses(
        segments: list[tuple[float, float, float, float]]) -> None:
    grid = rasterise(Map(segments, BOUNDS), RESOLUTION)
    height, width = grid_shape(BOUNDS, RESOLUTION)
    assert grid.shape == (height, width) == (12, 16)
    lines = [LineString([(x1, y1), (x2, y2)]) for x1, y1, x2, y2 in segments]
    for row in range(height):
        for col in range(width):
            x0, y0 = BOUNDS[0] + col * RESOLUTION, BOUNDS[1] + row * RESOLUTION
            cell = box(x0, y0, x0 + RESOLUTION, y0 + RESOLUTION)
            inner = box(x0 + 1e-9, y0 + 1e-9, x0 + RESOLUTION - 1e-9, y0 + RESOLUTION - 1e-9)
            if any(line.intersects(inner) for line in lines):
                assert grid[row, col], (row, col)
            if not any(line.distance(cell) < 1e-9 for line in lines):
                assert not grid[row, col], (row, col)


def test_walls_on_the_bounds_fall_in_the_edge_cells() -> None:
    grid = rasterise(Map.box(2.0, 1.0), 0.5)  # walls exactly on all four bounds
    expected = np.ones((2, 4), dtype=bool)
    assert np.array_equal(grid, expected)  # a 2-row grid: every cell touches an edge
    assert not rasterise(Map([(5, 5, 6, 6)], (0, 0, 2, 1)), 0.5).any()  # outside: no cell


@pytest.fixture(scope="module")
def plain_run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("plain") / "run"
    mimics.simulate("line", "go_to_goal", robots=1, time=0.3, seed=1, out=folder)
    return folder


def error_line(capsys: pytest.CaptureFixture[str], args: list[str]) -> str:
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("mimics: error: ")
    return err


def test_export_errors_are_one_line_with_status_2(plain_run: Path, tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    out = str(tmp_path / "x.mcap")
    assert "not a run folder" in error_line(capsys, ["export", str(tmp_path), "--mcap", out])
    assert "no such directory" in error_line(capsys, ["export", str(tmp_path / "nope"),
                                                      "--mcap", out])
    assert "recorded no laser scans" in error_line(capsys, ["export", str(plain_run), "--mcap",
                                                           out, "--scans"])
    assert "nothing to write" in error_line(capsys, ["export", str(plain_run)])
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    assert f"the folder {str(blocker)!r} is not a folder" in error_line(
        capsys, ["export", str(plain_run), "--bag", str(blocker / "run.bag")])
    # a folder that does not exist is refused, not created
    missing = tmp_path / "no" / "such"
    for option in ("--bag", "--mcap"):
        target = missing / f"run.{option[2:]}"
        assert error_line(capsys, ["export", str(plain_run), option, str(target)]) == (
            f"mimics: error: {target}: the folder {str(missing)!r} does not exist "
            "(create it first)")
    assert not (tmp_path / "no").exists()
    assert "is a directory" in error_line(capsys, ["export", str(plain_run), "--mcap",
                                                   str(tmp_path)])
    assert "resolution" in error_line(capsys, ["export", str(plain_run), "--mcap", out,
                                               "--resolution", "-1"])
    assert not list(tmp_path.glob("*.mcap")) and not list(tmp_path.glob(".x.mcap*"))


def test_export_replaces_an_old_file_and_no_scans_leaves_them_out(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "run"
    mimics.simulate("line", "go_to_goal", robots=1, time=0.3, seed=1, out=folder,
                    record_scans=True)
    target = tmp_path / "run.mcap"
    target.write_text("old")
    assert main(["export", str(folder), "--mcap", str(target), "--no-scans"]) == 0
    assert "wrote" in capsys.readouterr().out
    assert target.read_bytes()[:5] == b"\x89MCAP"
    from rosbags.highlevel import AnyReader

    with AnyReader([target]) as reader:
        assert "/robot_0/scan" not in {c.topic for c in reader.connections}
        assert "/robot_0/ground_truth" in {c.topic for c in reader.connections}
