"""Plain, TOML and JSON map files: round trips, default bounds, one-line errors."""

from pathlib import Path

import numpy as np
import pytest

from mimics.world.errors import MimicsError
from mimics.world.map_files import load_map, save_map
from mimics.world.maps import DEFAULT_MARGIN, Map, bounds_around
from tests.file_errors import file_error


def awkward_map() -> Map:
    rng = np.random.default_rng(3)
    segments = rng.uniform(-5, 5, size=(40, 4))
    segments[0] = [0.1, 0.2, 1 / 3, 2 / 3]  # floats without a short decimal form
    return Map(segments, (-6.0, -6.5, 6.25, 7.0), name="awkward")


@pytest.mark.parametrize("suffix", [".txt", ".map", ".segments", ".toml", ".json"])
def test_round_trip_is_exact(tmp_path: Path, suffix: str) -> None:
    original = awkward_map()
    path = save_map(original, tmp_path / f"walls{suffix}")
    loaded = load_map(path)
    assert loaded == original
    assert np.array_equal(loaded.segments, original.segments)
    assert loaded.bounds == original.bounds


def test_plain_file_with_comments_commas_and_bounds(tmp_path: Path) -> None:
    path = tmp_path / "room.txt"
    path.write_text("# a room\n\nbounds -1 -1 5 4   # the world\n0 0 4 0\n4,0, 4,3  # east\n"
                    "   4 3 0 3\n")
    room = load_map(path)
    assert room.bounds == (-1.0, -1.0, 5.0, 4.0)
    assert room.segments.tolist() == [[0, 0, 4, 0], [4, 0, 4, 3], [4, 3, 0, 3]]
    assert room.name == "room"


def test_bounds_default_to_the_walls_box_plus_a_margin(tmp_path: Path) -> None:
    path = tmp_path / "w.map"
    path.write_text("0 0 4 0\n1 -2 1 3\n")
    assert DEFAULT_MARGIN == 1.0
    assert load_map(path).bounds == (-1.0, -3.0, 5.0, 4.0)
    assert bounds_around(np.array([[0.0, 0.0, 2.0, 1.0]]), 0.5) == (-0.5, -0.5, 2.5, 1.5)


@pytest.mark.parametrize(("text", "line", "expected"), [
    ("0 0 1 1\n0 0 1\n", 2, "expected 'x1 y1 x2 y2'"),
    ("0 0 1 x\n", 1, "four numbers"),
    ("bounds 0 0 1\n", 1, "'bounds xmin ymin xmax ymax'"),
    ("bounds 0 0 1 1\nbounds 0 0 2 2\n", 2, "a second 'bounds' line"),
    ("0 0 nan 1\n", 1, "four numbers"),
])
def test_plain_file_errors_name_file_and_line(tmp_path: Path, text: str, line: int,
                                              expected: str) -> None:
    assert expected in file_error(load_map, tmp_path / "bad.txt", text, line=line)


def test_empty_and_inverted_maps_are_errors(tmp_path: Path) -> None:
    empty = tmp_path / "empty.txt"
    empty.write_text("# nothing here\n")
    with pytest.raises(MimicsError, match="no walls and no bounds"):
        load_map(empty)
    only_bounds = tmp_path / "field.txt"
    only_bounds.write_text("bounds 0 0 10 10\n")
    assert len(load_map(only_bounds).segments) == 0
    inverted = tmp_path / "inverted.txt"
    inverted.write_text("bounds 5 0 1 10\n")
    with pytest.raises(MimicsError, match=r"inverted\.txt: .*xmin < xmax"):
        load_map(inverted)


@pytest.mark.parametrize(("suffix", "text", "expected"), [
    (".toml", "segments = [[0, 0, 1, 1]]\nwalls = 3\n", "unknown key 'walls'"),
    (".toml", "segments = [[0, 0, 1]]\n", r"segments\[0\] must be \[x1, y1, x2, y2\]"),
    (".toml", "segments = [[0, 0, 1, 1]]\nbounds = [0, 0]\n", "bounds must be"),
    (".toml", "segments = [[0, 0, 1, 1]\n", "not valid TOML"),
    (".json", '{"segments": [[0, 0, 1, 1]],\n "bounds": [0, 0, 1, 1}', "line 2: not valid JSON"),
    (".json", '[1, 2]', "expected an object"),
])
def test_data_file_errors(tmp_path: Path, suffix: str, text: str, expected: str) -> None:
    path = tmp_path / f"bad{suffix}"
    path.write_text(text)
    with pytest.raises(MimicsError, match=expected) as info:
        load_map(path)
    assert str(path) in str(info.value)


def test_unknown_suffix_missing_file_and_wrong_options(tmp_path: Path) -> None:
    with pytest.raises(MimicsError, match=r"unknown map file type '\.dxf'"):
        load_map(tmp_path / "plan.dxf")
    with pytest.raises(MimicsError, match="map file not found"):
        load_map(tmp_path / "nothing.txt")
    path = save_map(awkward_map(), tmp_path / "m.txt")
    with pytest.raises(MimicsError, match="option 'scale' does not apply"):
        load_map(path, scale=2.0)
    with pytest.raises(MimicsError, match="can save a map as"):
        save_map(awkward_map(), tmp_path / "m.svg")
    with pytest.raises(MimicsError, match="unknown built-in map 'stage:moon'"):
        load_map("stage:moon")
