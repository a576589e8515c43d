"""Helpers of the workbench's browser tests (their fixtures are in conftest.py)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest


def screenshot(page: Any, tmp_path_factory: pytest.TempPathFactory, name: str) -> Path:
    """Save the page as ``screenshots/NAME.png`` under pytest's temporary folder."""
    shot = tmp_path_factory.getbasetemp() / "screenshots" / f"{name}.png"
    shot.parent.mkdir(exist_ok=True)
    page.screenshot(path=str(shot))
    print(f"screenshot: {shot}")
    return shot


def click_world(page: Any, editor: str, x: float, y: float) -> None:
    """Click the canvas of ``editor`` (maps, scenarios) at world point (x, y) in metres."""
    px, py = page.evaluate(f"window.workbench.{editor}.view.toScreen({x}, {y})")
    box = page.get_by_label(f"{editor[:-1].capitalize()} canvas").bounding_box()
    page.mouse.click(box["x"] + px, box["y"] + py)


def message(page: Any) -> Any:
    return page.get_by_role("status")


def take_refusals(page: Any, status: int) -> int:
    """Take the console's "status of STATUS" lines (the API refusing what a test sent on
    purpose) out of the page's console errors; returns how many there were."""
    errors = page.console_errors
    mine = [e for e in errors if f"the server responded with a status of {status} " in e]
    errors[:] = [e for e in errors if e not in mine]
    return len(mine)
