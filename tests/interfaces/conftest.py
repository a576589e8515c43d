"""What the interfaces' browser tests share: Debian's Chromium driven by Playwright."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from typing import Any

import pytest
from playwright import sync_api as playwright_api

from tests.system_packages import require


@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    require("chromium")
    with playwright_api.sync_playwright() as driver:
        launched = driver.chromium.launch(executable_path=shutil.which("chromium"),
                                          args=["--no-sandbox"])
        yield launched
        launched.close()
