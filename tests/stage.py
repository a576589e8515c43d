"""The Stage data files the tests use, from the data folder (never part of the project)."""

import os
from pathlib import Path

import pytest

from mimics.world.data_folder import find_stage_file
from mimics.world.errors import MimicsError


def stage_file(name: str) -> Path:
    """A Stage data file; the test is skipped where no data folder holds it.

    CI runs with ``../shared/data`` beside the clone: there a missing file is a
    failure, never a silent skip.
    """
    try:
        return find_stage_file(name)
    except MimicsError as exc:
        if os.environ.get("CI"):
            pytest.fail(f"{exc} (CI has ../shared/data beside the clone)")
        pytest.skip(str(exc))


# The Stage files each built-in Stage scenario reads (its robots' poses, its map's bitmap)
STAGE_SCENARIOS = {"cave": ("cave.world", "cave_filled.png"),
                   "hospital": ("hospital.world", "hospital.png")}


def needs_stage_scenario(name: str) -> None:
    """Skip the test (fail it on CI) when ``name`` is a Stage scenario whose data is missing.

    For tests parametrized over scenarios, some of them Stage's: call it first.
    """
    for file in STAGE_SCENARIOS.get(name, ()):
        stage_file(file)
