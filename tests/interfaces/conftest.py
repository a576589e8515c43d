"""What the interfaces' browser tests share: Debian's Chromium driven by Playwright."""

from __future__ import annotations

import shutil
from collections.abc import Iterator
from typing import Any

import pytest
from playwright import sync_api as playwright_api

from tests.system_packages import require

# A live run's end writes its folder in a process of its own; on a loaded 2-core CI
# machine that took over Playwright's default 5 s, so a page's wait for the outcome of
# a run (not for the page itself) gets 20 s before it counts as failed.
playwright_api.expect.set_options(timeout=20_000)

@pytest.fixture(scope="module")
def browser() -> Iterator[Any]:
    require("chromium")
    with playwright_api.sync_playwright() as driver:
        launched = driver.chromium.launch(executable_path=shutil.which("chromium"),
                                          args=["--no-sandbox"])
        yield launched
        launched.close()
