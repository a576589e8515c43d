"""The Stage data files the tests use, from the data folder (never part of the project).

A fresh clone has no Stage data: a test that reads it must say so through
:func:`stage_file` or :func:`needs_stage_scenario`, which skip it there. So that
a test that forgets cannot pass here and fail there, the suite hides the data
(:func:`hide_stage_data`, from ``tests/conftest.py``): ``MIMICS_DATA`` names an
empty folder, in the test's process and in every process it starts (a
subprocess, a battery worker, a Dask worker); the guards give the real folder
back for the test that asked, until its end.
"""

import os
import tempfile
from pathlib import Path

import pytest

from mimics.world.data_folder import ENV_VAR, data_folder, find_stage_file
from mimics.world.errors import MimicsError

#: The data folder the suite would have used, for the guards (set once, inherited).
REAL_DATA_VAR = "MIMICS_TEST_REAL_DATA"


def _empty_folder() -> Path:
    folder = Path(tempfile.gettempdir()) / f"mimics-tests-no-data-{os.getuid()}"
    folder.mkdir(exist_ok=True)
    return folder


def hide_stage_data() -> None:
    """Point ``MIMICS_DATA`` at an empty folder (the real one kept for the guards)."""
    if not os.environ.get(REAL_DATA_VAR):
        os.environ[REAL_DATA_VAR] = str(data_folder())
    os.environ[ENV_VAR] = str(_empty_folder())


def _real_data() -> Path:
    return Path(os.environ.get(REAL_DATA_VAR) or data_folder())


def stage_file(name: str) -> Path:
    """A Stage data file; the test is skipped where no data folder holds it.

    CI runs with ``../shared/data`` beside the clone: there a missing file is a
    failure, never a silent skip.
    """
    hidden = os.environ.get(ENV_VAR)
    os.environ[ENV_VAR] = str(_real_data())  # this test (and its children) may read it
    try:
        return find_stage_file(name)
    except MimicsError as exc:
        if hidden is not None:
            os.environ[ENV_VAR] = hidden
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
