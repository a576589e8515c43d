"""Native-algorithm tests build into a private cache (never the user's), shared per test worker."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.system_packages import require

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
ALGORITHMS = Path(__file__).parent / "algorithms"


@pytest.fixture(scope="session")
def shared_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One cache folder for the session: each file compiles once per test worker."""
    return tmp_path_factory.mktemp("mimics-cache")


@pytest.fixture(autouse=True)
def native_cache(shared_cache: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """Point MIMICS_CACHE_DIR at the session's cache, and make sure a compiler is there."""
    require("compiler")
    monkeypatch.setenv("MIMICS_CACHE_DIR", str(shared_cache))
    return shared_cache
