"""The Batteries page: a battery that stopped no longer reads "running" in the list, and a
filter that hides every run says so (Playwright, Debian's Chromium)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from playwright import sync_api as playwright_api

expect = playwright_api.expect


def test_the_list_follows_the_battery_and_an_empty_filter_says_so(
        page: Any, site: tuple[str, Path]) -> None:
    url, root = site
    page.goto(f"{url}/#/batteries")
    page.get_by_label("Battery name").fill("tiny")
    page.get_by_role("group", name="Algorithms").get_by_label("go_to_goal", exact=True).check()
    page.get_by_role("group", name="Scenarios").get_by_label("line", exact=True).check()
    page.get_by_label("Seeds", exact=True).fill("2")
    page.get_by_label("Simulated seconds per run").fill("0.3")
    page.get_by_label("Simulated seconds per run").blur()
    expect(page.get_by_text("2 runs", exact=True)).to_be_visible()
    page.get_by_role("button", name="Start battery").click()
    expect(page.get_by_label("Progress", exact=True)).to_contain_text(
        "2 of 2 runs finished (stopped", timeout=90_000)
    entry = page.get_by_role("button", name="batteries/tiny (")
    expect(entry).to_have_text("batteries/tiny (2 runs, finished)")  # not "running"
    table = page.get_by_role("table", name="Runs of the battery")
    expect(table.locator("tbody tr")).to_have_count(2)
    page.get_by_label("Filter runs").fill("no such run")
    expect(table.locator("tbody tr")).to_have_count(1)
    expect(table.locator("tbody")).to_have_text("No run of the 2 matches the filter.")
    page.get_by_label("Filter runs").fill("")
    page.get_by_label("Only misbehaving runs").check()  # two good runs: none misbehaves
    expect(table.locator("tbody")).to_have_text(
        "No run of the 2 matches the filter (only misbehaving runs).")
    assert (root / "batteries" / "tiny" / "battery.db").is_file()
    # its plots: thumbnails that open full size (nobody reached a goal in 0.3 s: every run's
    # time to goal is the horizon and the arrival curves stay at 0; tests/interfaces/
    # test_plots.py checks the figures)
    page.get_by_role("button", name="Plots").click()
    for name in ("outcomes.png", "time_to_goal.png", "arrivals.png"):
        image = page.get_by_role("img", name=f"{name} of batteries/tiny")
        expect(image).to_be_visible(timeout=30_000)
        page.wait_for_function(f"""() => [...document.querySelectorAll('figure.thumbnail img')]
            .some((img) => img.alt.startsWith('{name}') && img.naturalWidth > 0)""")
    page.get_by_role("img", name="outcomes.png of batteries/tiny").click()
    dialog = page.get_by_role("dialog", name="Plot")
    expect(dialog).to_be_visible()
    assert dialog.get_by_role("img").bounding_box()["width"] > 800
    page.keyboard.press("Escape")
    expect(dialog).to_be_hidden()
