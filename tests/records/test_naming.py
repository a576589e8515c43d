"""Default run folder names: never one already taken, even by two runs started at once."""

from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from mimics.records.naming import new_run_folder, run_folder_name
from mimics.world.errors import MimicsError


def test_a_taken_name_gets_the_next_free_number(tmp_path: Path) -> None:
    first = new_run_folder(tmp_path, "room", "go_to_goal", 3)
    (first / "summary.json").write_text("{}")
    second = new_run_folder(tmp_path / ".", "room", "go_to_goal", 3)
    (tmp_path / "room-go_to_goal-s3-4").mkdir()  # a gap is not filled past a taken name
    third = new_run_folder(tmp_path, "room", "go_to_goal", 3)
    assert [first.name, second.name, third.name] == [
        "room-go_to_goal-s3", "room-go_to_goal-s3-2", "room-go_to_goal-s3-3"]
    assert (first / "summary.json").read_text() == "{}"  # the earlier run is untouched
    assert new_run_folder(tmp_path, "room", "go_to_goal", 3).name == "room-go_to_goal-s3-5"
    assert list(second.iterdir()) == []


def test_runs_started_at_once_get_distinct_folders(tmp_path: Path) -> None:
    with ThreadPoolExecutor(8) as pool:
        folders = list(pool.map(lambda _: new_run_folder(tmp_path, "x", "a", 0), range(40)))
    assert len(set(folders)) == 40
    assert sorted(f.name for f in tmp_path.iterdir()) == sorted(f.name for f in folders)


def test_unsafe_characters_become_one_underscore() -> None:
    assert run_folder_name("a/../b c", "my algo", -1) == "a_.._b_c-my_algo-s-1"


def test_an_unwritable_parent_is_one_clear_error(tmp_path: Path) -> None:
    (tmp_path / "file").write_text("")
    with pytest.raises(MimicsError, match="cannot make a run folder here"):
        new_run_folder(tmp_path / "file", "x", "a", 0)
