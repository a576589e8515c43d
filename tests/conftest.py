"""Suite-wide set-up: the system packages some tests need (see ``system_packages``)."""

from __future__ import annotations

import pytest
from hypothesis import settings

from tests.stage import hide_stage_data
from tests.system_packages import install_missing

# Hypothesis: no examples database (nothing written to .hypothesis/, nothing to keep out of
# git) and derandomized, so that CI runs the same examples every time.
settings.register_profile("mimics", database=None, derandomize=True)
settings.load_profile("mimics")


def pytest_configure(config: pytest.Config) -> None:
    hide_stage_data()  # before any test is collected, in every worker too
    if hasattr(config, "workerinput"):  # an xdist worker: the main process did it
        return
    note = install_missing()
    if note:
        print(f"mimics tests: system packages: {note}")


@pytest.fixture(autouse=True)
def _stage_data_hidden() -> object:
    """The Stage data hidden again after each test (a guard gave it to that test only)."""
    yield
    hide_stage_data()
