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


def replay_pixels(page: Any, x: float, y: float, size: int = 3) -> list[list[int]]:
    """RGB of the replay canvas's ``size`` x ``size`` pixels around world point (x, y)."""
    half = size // 2
    data = page.evaluate(f"""() => {{
        const view = window.workbench.runs.view;
        const [px, py] = view.toScreen({x}, {y});
        const ratio = window.devicePixelRatio || 1;
        return Array.from(view.context.getImageData(Math.round(px * ratio) - {half},
                                                   Math.round(py * ratio) - {half},
                                                   {size}, {size}).data);
    }}""")
    return [data[k:k + 3] for k in range(0, len(data), 4)]


def fill_battery_form(page: Any, name: str, robots: str, seeds: int, runs: int) -> None:
    """On the Batteries page: go_to_goal on the line scenario with ``robots`` (its
    parameter text), ``seeds`` seeds of 0.5 s; waits until the form counts ``runs``."""
    from playwright.sync_api import expect

    page.get_by_label("Battery name").fill(name)
    page.get_by_role("group", name="Algorithms").get_by_label("go_to_goal", exact=True).check()
    scenarios = page.get_by_role("group", name="Scenarios")
    scenarios.get_by_label("line", exact=True).check()
    scenarios.get_by_label("Parameters of line", exact=True).fill(f"robots={robots}")
    page.get_by_label("Seeds", exact=True).fill(str(seeds))
    page.get_by_label("Simulated seconds per run").fill("0.5")
    page.get_by_label("Simulated seconds per run").blur()
    expect(page.get_by_text(f"{runs} runs", exact=True)).to_be_visible()

