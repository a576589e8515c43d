"""Suite-wide set-up: the system packages some tests need (see ``system_packages``)."""

from __future__ import annotations

import pytest

from tests.system_packages import install_missing


def pytest_configure(config: pytest.Config) -> None:
    if hasattr(config, "workerinput"):  # an xdist worker: the main process did it
        return
    note = install_missing()
    if note:
        print(f"mimics tests: system packages: {note}")
