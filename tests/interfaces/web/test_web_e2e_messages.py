"""The message line: worded for the page, one line however long, and an old error goes when
the next action succeeds (Playwright, Debian's Chromium)."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from playwright import sync_api as playwright_api

from tests.interfaces.web.browser import click_world, message, take_refusals

expect = playwright_api.expect


def test_a_long_error_keeps_the_header_on_one_line_and_goes_after_a_success(
        page: Any, site: tuple[str, Path]) -> None:
    url, root = site
    (root / "maps").mkdir(exist_ok=True)
    (root / "maps" / "hall.txt").write_text("bounds 0 0 12 8\n0 0 12 0\n0 8 12 8\n")
    page.set_viewport_size({"width": 900, "height": 700})
    page.goto(f"{url}/#/scenarios")
    header = page.locator("header")
    expect(page.get_by_role("link", name="Runs")).to_be_visible()
    one_line = header.bounding_box()["height"]
    page.get_by_label("Map", exact=True).select_option("maps/hall.txt")
    page.get_by_role("button", name="Line").click()
    page.get_by_label("Count", exact=True).fill("8")
    page.get_by_label("Goal offset dx, dy (m)").fill("0, 3")
    click_world(page, "scenarios", 2.0, 2.0)
    click_world(page, "scenarios", 3.0, 2.0)  # 8 robots in 1 m: they overlap
    page.get_by_label("Save scenario as").fill("scenarios/crowd.toml")
    page.get_by_role("button", name="Save scenario").click()
    line = message(page)
    expect(line).to_have_class("error")
    text = line.text_content()
    assert text.startswith("robot 0 at (2, 2) and robot 1 at (2.14286, 2) overlap at the start")
    assert "--allow-overlap" not in text and "line " not in text and "robots[" not in text
    assert line.get_attribute("title") == text  # the whole message, as a tooltip
    assert header.bounding_box()["height"] == one_line  # the header did not wrap
    assert line.evaluate("e => e.scrollWidth > e.clientWidth")  # cut with an ellipsis
    assert not (root / "scenarios" / "crowd.toml").exists()
    named = sorted({int(k) for k in re.findall(r"\brobot (\d+)", text)})
    assert len(named) >= 2  # the robots the message names are the ones drawn in red
    assert sorted(page.evaluate("window.workbench.scenarios.fault.robots")) == named
    page.get_by_role("button", name="Remove all").click()  # the next action succeeds
    expect(line).to_have_text("")
    expect(line).not_to_have_class("error")
    page.get_by_role("button", name="One").click()
    click_world(page, "scenarios", 6.0, 0.0)
    click_world(page, "scenarios", 6.0, 4.0)
    page.get_by_role("button", name="Save scenario").click()
    expect(line).to_have_text("robot 0: robot at (6, 0) touches wall 0 (0, 0)-(12, 0) at the "
                              "start (expected it in free space)")
    fault = page.evaluate("window.workbench.scenarios.fault")
    assert fault == {"robots": [0], "walls": [[0, 0, 12, 0]]}  # drawn in red
    page.wait_for_function("""() => {  // the wall at fault, red on the canvas
        const view = window.workbench.scenarios.view;
        const [px, py] = view.toScreen(3, 0);
        const ratio = window.devicePixelRatio || 1;
        const [r, g, b] = view.context.getImageData(Math.round(px * ratio),
                                                    Math.round(py * ratio), 1, 1).data;
        return r === 198 && g === 40 && b === 40;
    }""", timeout=5000)
    page.get_by_label("Map", exact=True).select_option("maps/hall.txt")  # reloads the map: OK
    expect(line).to_have_text("")
    assert take_refusals(page, 422) == 2  # the two saves refused
