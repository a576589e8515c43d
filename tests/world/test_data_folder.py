"""Where the Stage data is found: MIMICS_DATA, the user folder, then a development checkout."""

from pathlib import Path

import pytest

from mimics.world import data_folder as df
from mimics.world.errors import MimicsError


@pytest.fixture
def user_folder(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    folder = tmp_path / "user-data"
    monkeypatch.setattr(df, "user_data_folder", lambda: folder)
    monkeypatch.delenv(df.ENV_VAR, raising=False)
    return folder


def test_environment_variable_comes_first(user_folder: Path, tmp_path: Path,
                                          monkeypatch: pytest.MonkeyPatch) -> None:
    (user_folder / "stage").mkdir(parents=True)
    monkeypatch.setenv("MIMICS_DATA", str(tmp_path / "mine"))
    assert df.data_folder() == tmp_path / "mine"
    assert df.download_folder() == tmp_path / "mine"


def test_user_folder_when_it_holds_stage(user_folder: Path) -> None:
    (user_folder / "stage").mkdir(parents=True)
    assert df.data_folder() == user_folder


def test_development_checkout_then_user_folder(user_folder: Path,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    checkout = df._checkout_data_folder()
    if checkout is not None:  # in this repository's setup: ../shared/data
        assert (checkout / "stage").is_dir() and checkout.parts[-2:] == ("shared", "data")
        assert df.data_folder() == checkout
    monkeypatch.setattr(df, "_checkout_data_folder", lambda: None)
    assert df.data_folder() == user_folder
    assert df.download_folder() == user_folder


def test_missing_file_says_how_to_get_it(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("MIMICS_DATA", str(tmp_path))
    with pytest.raises(MimicsError) as info:
        df.find_stage_file("cave_filled.png")
    message = str(info.value)
    assert "'cave_filled.png' not found in" in message and str(tmp_path / "stage") in message
    assert "mimics data get stage" in message and "MIMICS_DATA" in message
    assert "\n" not in message
    (tmp_path / "stage").mkdir()
    (tmp_path / "stage" / "cave_filled.png").write_bytes(b"png")
    assert df.find_stage_file("cave_filled.png") == tmp_path / "stage" / "cave_filled.png"
