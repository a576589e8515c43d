"""The Runs page: the list shows each run's state and robot count, the replay draws goals,
headings and ids as the exported video does, and Play/Pause show which is in effect
(Playwright, Debian's Chromium)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from playwright import sync_api as playwright_api

from mimics.records.run_folder import load_run
from tests.interfaces.web.browser import replay_pixels

expect = playwright_api.expect


def test_the_list_the_drawing_and_the_play_buttons(page: Any, site: tuple[str, Path]) -> None:
    url, root = site
    run = load_run(root / "runs" / "line-go_to_goal-s1")
    page.goto(f"{url}/#/runs")
    entry = page.get_by_role("button", name="runs/line-go_to_goal-s1")
    expect(entry).to_contain_text(f"{run.summary['status']}, 3 robots")
    page.evaluate("""() => {  // record the text the page writes on its canvases
        window.written = [];
        const fill = CanvasRenderingContext2D.prototype.fillText;
        CanvasRenderingContext2D.prototype.fillText = function (text, ...rest) {
            window.written.push(String(text));
            return fill.call(this, text, ...rest);
        };
    }""")
    entry.click()
    clock = page.get_by_label("Simulated time")
    expect(clock).to_have_text("t = 0.00 s")
    play = page.get_by_role("button", name="Play")
    pause = page.get_by_role("button", name="Pause")
    expect(play).to_have_attribute("aria-pressed", "false")
    expect(pause).to_have_attribute("aria-pressed", "true")
    page.wait_for_function("window.written.length >= 3")  # drawn at the next animation frame
    assert sorted(set(page.evaluate("window.written"))) == ["0", "1", "2"]  # the robot ids
    x, y, theta = run.scenario.stages[0, :3]
    half_length = float(run.scenario.robot_type(0).length) / 2
    tip = 0.6 * half_length  # on the heading line, inside the body
    assert [255, 255, 255] in replay_pixels(page, x + tip * np.cos(theta), y + tip * np.sin(theta))
    gx, gy = run.scenario.goals[0]
    assert [0x7A, 0x7A, 0x7A] in replay_pixels(page, gx, gy)  # the goal's grey cross
    play.click()
    expect(play).to_have_attribute("aria-pressed", "true")
    expect(pause).to_have_attribute("aria-pressed", "false")
    pause.click()
    expect(play).to_have_attribute("aria-pressed", "false")
    expect(pause).to_have_attribute("aria-pressed", "true")
