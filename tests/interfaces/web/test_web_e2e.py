"""The workbench in a real headless Chromium (Debian's package, driven by Playwright).

The fixtures (conftest.py, browser.py): the server runs in a thread of the test process
(uvicorn on a free port). Every test fails on a console error of the page, and saves a
screenshot of its page under pytest's temporary folder (the path is printed).
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import imageio.v3 as imageio
import numpy as np
import pytest
from playwright import sync_api as playwright_api

from mimics.interfaces.cli import main
from mimics.records.run_folder import load_run
from mimics.world.map_files import load_map
from tests.interfaces.web.browser import click_world, fill_battery_form, message, screenshot


def test_every_page_opens_from_the_navigation(page: Any, site: tuple[str, Path]) -> None:
    page.goto(site[0])
    expect = playwright_api.expect
    for name in ("Scenarios", "Batteries", "Runs", "Maps"):
        page.get_by_role("link", name=name).click()
        expect(page.get_by_role("link", name=name)).to_have_attribute("aria-current", "page")
        expect(page.get_by_role("region", name=name)).to_be_visible()


def test_draw_two_walls_and_save(page: Any, site: tuple[str, Path]) -> None:
    url, root = site
    page.goto(f"{url}/#/maps")
    page.get_by_role("button", name="New map").click()
    page.get_by_role("button", name="Segment").click()
    for x, y in ((1.0, 1.0), (6.0, 1.0), (2.5, 3.0), (2.5, 8.5)):
        click_world(page, "maps", x + 0.1, y - 0.1)  # off by less than half a grid step
    page.get_by_label("Save as").fill("maps/two.txt")
    page.get_by_role("button", name="Save map").click()
    playwright_api.expect(message(page)).to_have_text("saved maps/two.txt: 2 walls")
    the_map = load_map(root / "maps" / "two.txt")
    assert the_map.segments.tolist() == [[1.0, 1.0, 6.0, 1.0], [2.5, 3.0, 2.5, 8.5]]
    assert the_map.bounds == (0.0, 0.0, 10.0, 10.0)


def test_rectangle_undo_redo_move_a_vertex_delete_and_import(
        page: Any, site: tuple[str, Path], tmp_path: Path) -> None:
    url, root = site
    page.goto(f"{url}/#/maps")
    page.get_by_role("button", name="New map").click()
    page.get_by_role("button", name="Rectangle").click()
    click_world(page, "maps", 2.0, 2.0)
    click_world(page, "maps", 6.0, 5.0)
    walls = page.get_by_label("Wall count")
    playwright_api.expect(walls).to_have_text("4 walls")
    page.get_by_role("button", name="Undo").click()
    playwright_api.expect(walls).to_have_text("0 walls")
    page.get_by_role("button", name="Redo").click()
    playwright_api.expect(walls).to_have_text("4 walls")
    page.get_by_role("button", name="Select").click()
    box = page.get_by_label("Map canvas").bounding_box()
    corner = page.evaluate("window.workbench.maps.view.toScreen(6, 5)")
    target = page.evaluate("window.workbench.maps.view.toScreen(7, 6)")
    page.mouse.move(box["x"] + corner[0], box["y"] + corner[1])
    page.mouse.down()
    page.mouse.move(box["x"] + target[0], box["y"] + target[1], steps=4)
    page.mouse.up()
    click_world(page, "maps", 2.0, 3.5)  # the west wall, away from its ends
    page.get_by_role("button", name="Delete").click()
    playwright_api.expect(walls).to_have_text("3 walls")
    page.get_by_label("Save as").fill("maps/moved.txt")
    page.get_by_role("button", name="Save map").click()
    playwright_api.expect(message(page)).to_have_text("saved maps/moved.txt: 3 walls")
    saved = sorted(map(tuple, load_map(root / "maps" / "moved.txt").segments.tolist()))
    assert saved == sorted([(2.0, 2.0, 6.0, 2.0), (6.0, 2.0, 7.0, 6.0), (7.0, 6.0, 2.0, 5.0)])
    drawing = tmp_path / "plan.svg"
    drawing.write_text('<svg xmlns="http://www.w3.org/2000/svg" width="100" height="50">'
                       '<rect x="10" y="10" width="30" height="20" fill="none" stroke="black"/>'
                       '</svg>')
    page.get_by_label("File to import").set_input_files(str(drawing))
    page.get_by_label("SVG scale (m/unit)").fill("0.1")
    page.get_by_role("button", name="Import", exact=True).click()
    playwright_api.expect(message(page)).to_have_text(
        "imported plan.svg: 4 walls (not saved yet)", timeout=30_000)
    assert not (root / "maps" / "plan.txt").exists()
    # a ROS map_server YAML and its image in the workspace: the same importer as the CLI's
    image = np.full((20, 30), 254, dtype=np.uint8)
    image[5:10, 10:15] = 0  # one occupied block
    imageio.imwrite(root / "maps" / "floor.pgm", image)
    (root / "maps" / "floor.yaml").write_text(
        "image: floor.pgm\nresolution: 0.05\norigin: [-1.0, -2.0, 0.0]\n"
        "occupied_thresh: 0.65\nfree_thresh: 0.196\nnegate: 0\n")
    expected = len(load_map(root / "maps" / "floor.yaml").segments)
    page.get_by_label("File to import").set_input_files(str(root / "maps" / "floor.yaml"))
    questions: list[str] = []  # the imported drawing is not saved: the page asks first
    page.once("dialog", lambda d: (questions.append(d.message), d.accept()))
    page.get_by_role("button", name="Import", exact=True).click()
    playwright_api.expect(message(page)).to_have_text(
        f"imported floor.yaml: {expected} walls (not saved yet)", timeout=30_000)
    assert questions == ["Unsaved edits to this map will be lost. Continue?"]


def test_place_a_line_of_robots_save_and_mimics_run_runs_it(
        page: Any, site: tuple[str, Path], tmp_path: Path) -> None:
    url, root = site
    (root / "maps" / "room.txt").write_text("bounds 0 0 12 8\n0 0 12 0\n0 8 12 8\n")
    page.goto(f"{url}/#/scenarios")
    page.get_by_label("Map", exact=True).select_option("maps/room.txt")
    playwright_api.expect(page.get_by_text("0 robots on maps/room.txt")).to_be_visible()
    page.get_by_label("Count", exact=True).fill("4")
    page.get_by_label("Goal offset dx, dy (m)").fill("6, 0")
    page.get_by_role("button", name="Line").click()
    click_world(page, "scenarios", 2.0, 1.5)
    click_world(page, "scenarios", 2.0, 6.0)
    playwright_api.expect(page.get_by_text("4 robots on maps/room.txt")).to_be_visible()
    page.get_by_label("Time limit (s)").fill("5")
    page.get_by_label("Save scenario as").fill("scenarios/line4.toml")
    page.get_by_role("button", name="Save scenario").click()
    playwright_api.expect(message(page)).to_have_text("saved scenarios/line4.toml: 4 robots")
    out = tmp_path / "run"
    code = main(["run", str(root / "scenarios" / "line4.toml"), "go_to_goal", "--time", "1",
                 "--out", str(out), "--robot-logs", "off"])
    assert code in (0, None)
    run = load_run(out)
    assert run.summary["robots"] == 4 and run.summary["sim_time"] == 1.0
    starts = run.scenario.stages[:, :2]
    assert starts[:, 0] == pytest.approx([2.0] * 4, abs=0.1)
    assert starts[:, 1] == pytest.approx([1.5, 3.0, 4.5, 6.0], abs=0.1)
    assert (run.scenario.goals - starts).ravel() == pytest.approx([6.0, 0.0] * 4)
    page.get_by_label("Algorithm", exact=True).select_option("go_to_goal")
    page.get_by_role("button", name="Run", exact=True).click()  # run once, open the replay
    playwright_api.expect(page).to_have_url(
        re.compile(r"#/runs\?path=runs%2Fscenario-go_to_goal-s0"), timeout=60_000)
    playwright_api.expect(page.get_by_label("Simulated time")).to_have_text("t = 0.00 s")
    assert load_run(root / "runs" / "scenario-go_to_goal-s0").summary["sim_time"] == 5.0


def test_start_a_battery_of_four_runs_and_watch_it_finish(
        page: Any, site: tuple[str, Path], tmp_path_factory: pytest.TempPathFactory) -> None:
    url, root = site
    page.goto(f"{url}/#/batteries")
    fill_battery_form(page, "four", robots="1,2", seeds=2, runs=4)
    page.get_by_role("button", name="Start battery").click()
    progress = page.get_by_label("Progress", exact=True)
    playwright_api.expect(progress).to_contain_text("4 of 4 runs finished (stopped",
                                                    timeout=90_000)
    table = page.get_by_role("table", name="Runs of the battery")
    playwright_api.expect(table.locator("tbody tr")).to_have_count(4)
    assert (root / "batteries" / "four" / "battery.db").is_file()
    page.reload()  # the state comes from SQLite, so a reload shows the same
    playwright_api.expect(progress).to_contain_text("4 of 4 runs finished")
    playwright_api.expect(table.locator("tbody tr")).to_have_count(4)
    screenshot(page, tmp_path_factory, "batteries_page")  # this test ends on the Runs page
    table.locator("tbody tr").first.click()
    playwright_api.expect(page).to_have_url(re.compile(r"#/runs\?path=batteries%2Ffour"))
    playwright_api.expect(page.get_by_label("Simulated time")).to_have_text("t = 0.00 s")


def test_a_stopping_rule_battery_shows_its_evidence(page: Any, site: tuple[str, Path]) -> None:
    url, root = site
    page.goto(f"{url}/#/batteries")
    page.get_by_label("Battery name").fill("rule")
    algorithms = page.get_by_role("group", name="Algorithms")
    algorithms.get_by_label("go_to_goal", exact=True).check()
    algorithms.get_by_label("wall_aware", exact=True).check()
    page.get_by_role("group", name="Scenarios").get_by_label("line", exact=True).check()
    page.get_by_label("Simulated seconds per run").fill("0.5")
    page.get_by_label("Minimum seeds").fill("3")
    page.get_by_label("Maximum seeds").fill("4")
    page.get_by_label("Stop when").fill("collisions:0.5")
    page.get_by_label("Stop when").blur()
    playwright_api.expect(page.get_by_text("6 runs in the first round, at most 8",
                                           exact=True)).to_be_visible()
    page.get_by_role("button", name="Start battery").click()
    progress = page.get_by_label("Progress", exact=True)
    # no collision in 0.5 s: no spread, on which the rule never stops: max_seeds, unmet
    playwright_api.expect(progress).to_contain_text("8 of 8 runs finished (stopped",
                                                    timeout=90_000)
    rule = page.get_by_role("table", name="Stopping rule")
    playwright_api.expect(rule).to_contain_text("Until the 95% interval of collisions is "
                                                "within ± 0.5")
    playwright_api.expect(rule.locator("tbody tr")).to_have_count(2)
    playwright_api.expect(rule.locator("tbody tr").first).to_contain_text("4 of 4")
    playwright_api.expect(rule.locator("tbody tr").first).to_contain_text("max seeds")
    unmet = page.get_by_role("list", name="Targets not met")
    playwright_api.expect(unmet.locator("li")).to_have_count(2)
    playwright_api.expect(unmet.locator("li").first).to_contain_text(
        "target not met: go_to_goal x line")
    intervals = page.get_by_role("table", name="Intervals per cell")
    playwright_api.expect(intervals).to_contain_text("95% Wilson interval")
    playwright_api.expect(intervals.locator("tbody tr")).to_have_count(2)
    comparison = page.get_by_role("table", name="Paired comparison")
    playwright_api.expect(comparison).to_contain_text("against go_to_goal")
    playwright_api.expect(comparison.locator("tbody tr").first).to_contain_text("wall_aware")
    page.get_by_label("Baseline").select_option("wall_aware")
    playwright_api.expect(comparison).to_contain_text("against wall_aware")
    assert (root / "batteries" / "rule" / "battery.db").is_file()


def test_open_a_run_and_play_it(page: Any, site: tuple[str, Path]) -> None:
    url, _ = site
    page.goto(f"{url}/#/runs")
    page.get_by_role("button", name="runs/line-go_to_goal-s1").click()
    clock = page.get_by_label("Simulated time")
    playwright_api.expect(clock).to_have_text("t = 0.00 s")
    page.get_by_label("Speed").select_option("2")
    page.get_by_role("button", name="Play").click()
    playwright_api.expect(clock).not_to_have_text("t = 0.00 s")
    page.wait_for_timeout(300)
    page.get_by_role("button", name="Pause").click()
    paused = clock.text_content()
    seconds = float(paused.split()[2])
    assert 0.0 < seconds <= 3.0
    page.wait_for_timeout(400)
    assert clock.text_content() == paused  # paused: time stands still
