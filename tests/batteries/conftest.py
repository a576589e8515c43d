"""Battery tests never touch the user's config folder."""

from __future__ import annotations

from pathlib import Path

import pytest


@pytest.fixture(autouse=True)
def config_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A private MIMICS_CONFIG_DIR for each test."""
    folder = tmp_path / "config"
    monkeypatch.setenv("MIMICS_CONFIG_DIR", str(folder))
    return folder
