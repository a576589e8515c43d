"""The live page (#/live/ID): the picture moves while the run runs and not while paused, Step
takes one step, the inspector shows a robot's values and beams (or every robot's), a drag
and a drawn wall change the run and its records, a refused edit says why, Stop ends it with
its folder complete; the Runs page lists it (Playwright, Debian's Chromium)."""

from __future__ import annotations

import json
import re
import tomllib
import urllib.request
from pathlib import Path
from typing import Any

from playwright import sync_api as playwright_api

from mimics.records.run_folder import load_run
from mimics.world.map_files import save_map
from mimics.world.maps import Map
from tests.interfaces.web.browser import fill_battery_form, take_refusals
from tests.interfaces.web.test_web_api import scenario_body

expect = playwright_api.expect


def call(url: str, method: str, body: Any = None) -> Any:
    request = urllib.request.Request(url, method=method, data=None if body is None else
                                     json.dumps(body).encode(),
                                     headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(request, timeout=300) as answer:
        return json.loads(answer.read())


def picture(page: Any) -> str:
    return page.evaluate("window.workbench.live.canvas.toDataURL()")


def drag(page: Any, start: tuple[float, float], end: tuple[float, float]) -> None:
    """Drag on the live canvas from world point ``start`` to ``end`` (metres)."""
    box = page.get_by_label("Live canvas").bounding_box()
    a = page.evaluate(f"window.workbench.live.view.toScreen({start[0]}, {start[1]})")
    b = page.evaluate(f"window.workbench.live.view.toScreen({end[0]}, {end[1]})")
    page.mouse.move(box["x"] + a[0], box["y"] + a[1])
    page.mouse.down()
    page.mouse.move(box["x"] + (a[0] + b[0]) / 2, box["y"] + (a[1] + b[1]) / 2)
    page.mouse.move(box["x"] + b[0], box["y"] + b[1])
    page.mouse.up()


def test_watch_pause_step_edit_and_stop_a_live_run(page: Any, site: tuple[str, Path]) -> None:
    url, root = site
    (root / "maps").mkdir(exist_ok=True)
    save_map(Map.box(10.0, 6.0, name="room"), root / "maps" / "room.txt")
    call(f"{url}/api/scenarios/file", "PUT", scenario_body(settings={"time_limit": 60.0}))
    run = call(f"{url}/api/live", "POST", {"scenario": "scenarios/two.toml",
                                           "algorithm": "go_to_goal", "seed": 2})
    live = "window.workbench.live"
    page.goto(f"{url}/#/live/{run['id']}")
    expect(page.get_by_label("Live state")).to_contain_text("running, recording runs/")
    # the action at hand is highlighted: Pause while it runs
    expect(page.get_by_role("button", name="Pause")).to_have_class("primary")
    expect(page.get_by_role("button", name="Resume")).to_be_disabled()
    page.wait_for_function(f"{live}.frame && {live}.frame.time > 0")
    first_time = page.evaluate(f"{live}.frame.time")
    before = picture(page)
    page.wait_for_function(f"{live}.frame.time > {first_time} + 0.5")
    page.wait_for_timeout(50)  # the next animation frame draws it
    assert picture(page) != before  # it moves while it runs
    # Pause: the picture holds still
    page.get_by_role("button", name="Pause").click()
    expect(page.get_by_role("button", name="Resume")).to_have_class("primary")
    expect(page.get_by_role("button", name="Pause")).to_be_disabled()
    expect(page.get_by_label("Live state")).to_contain_text("paused at t = ")
    page.wait_for_timeout(300)  # a step in flight at the Pause (under 1 ms for 2 robots) ends
    paused = call(f"{url}/api/live/{run['id']}", "GET")
    page.wait_for_function(f"Math.round({live}.frame.time * 10) === {paused['step']}")
    page.wait_for_timeout(100)
    held, frames = picture(page), page.evaluate(f"{live}.frames")
    page.wait_for_timeout(700)
    assert picture(page) == held and page.evaluate(f"{live}.frames") == frames
    assert call(f"{url}/api/live/{run['id']}", "GET")["step"] == paused["step"]
    # Step: one step of 0.1 s
    page.get_by_role("button", name="Step").click()
    page.wait_for_function(f"Math.round({live}.frame.time * 10) === {paused['step'] + 1}")
    expect(page.get_by_label("Simulated time")).to_contain_text(f"step {paused['step'] + 1}")
    # the inspector: a click on robot 0 shows its values now, from the worker
    inspector = page.get_by_label("Inspector")
    x0, y0 = page.evaluate(f"Array.from({live}.frame.poses.slice(0, 2))")
    drag(page, (x0, y0), (x0, y0))  # a click: selection only
    expect(inspector.locator('[data-field="type"]')).to_have_text("Pioneer2DX")
    expect(inspector.locator('[data-field="x"]')).to_have_text(f"{x0:.3f} m")
    expect(inspector.locator('[data-field="v"]')).not_to_have_text("n/a")
    # its beams, asked for, from the worker's last scan: Pioneer2DX's 180; every robot's:
    # robot 1's 30 too
    page.wait_for_timeout(300)
    assert page.evaluate(f"{live}.beams.length") == 0  # none unless asked for
    page.get_by_label("Selected robot's beams").check()
    page.wait_for_function(f"{live}.beams.length === 180")
    page.wait_for_timeout(50)  # the next animation frame draws them
    one_robot = picture(page)
    every = inspector.get_by_label("Every robot's beams")
    every.check()
    page.wait_for_function(f"{live}.beams.length === 210")
    page.wait_for_timeout(50)
    assert picture(page) != one_robot
    every.uncheck()
    page.wait_for_function(f"{live}.beams.length === 180")
    # a drag moves robot 1 (it stands still, no goal) to (5, 4.5); the inspector follows it
    x, y = page.evaluate(f"Array.from({live}.frame.poses.slice(3, 5))")
    drag(page, (x, y), (5.0, 4.5))
    expect(page.get_by_label("Last edit")).to_contain_text(f"step {paused['step'] + 1}")
    moved = page.evaluate(f"Array.from({live}.frame.poses.slice(3, 5))")
    assert abs(moved[0] - 5.0) < 0.1 and abs(moved[1] - 4.5) < 0.1
    expect(inspector.locator('[data-field="type"]')).to_have_text("Pioneer2DX_b30")
    expect(page.get_by_role("log", name="Robot log")).to_contain_text("edit: move robot 1")
    # a wall drawn across the room's lower half, clear of the robots
    page.get_by_label("Draw wall").check()
    walls = page.evaluate(f"{live}.meta.map.segments.length")
    drag(page, (6.5, 0.3), (6.5, 2.5))
    page.wait_for_function(f"{live}.meta.map.segments.length === {walls + 1}")
    # a wall through robot 0 is refused, in one line on the page
    robot = page.evaluate(f"Array.from({live}.frame.poses.slice(0, 2))")
    drag(page, (robot[0], robot[1] - 0.8), (robot[0], robot[1] + 0.8))
    # one sentence: no "edit:" prefix, no 7-digit floats
    alert = page.get_by_role("alert")
    expect(alert).to_contain_text("Edit refused: the wall would touch robot 0 at (")
    assert re.fullmatch(r"Edit refused: the wall would touch robot 0 at \(-?\d+(\.\d{1,3})?, "
                        r"-?\d+(\.\d{1,3})?\)\.", alert.text_content())
    assert take_refusals(page, 422) == 1
    assert page.evaluate(f"{live}.meta.map.segments.length") == walls + 1
    # the move broke robot 1's trail, as the replay breaks it
    assert page.evaluate(f"{live}.past.some((p) => p.jumped.has(1)) || "
                         f"{live}.frame.jumped.has(1)")
    # Fit view after a zoom: the whole map again
    page.get_by_label("Select / drag robot").check()
    scale = page.evaluate(f"{live}.view.scale")
    page.mouse.move(640, 300)
    page.mouse.wheel(0, -600)
    page.wait_for_function(f"{live}.view.scale > {scale} * 1.5")
    page.get_by_role("button", name="Fit view").click()
    assert abs(page.evaluate(f"{live}.view.scale") - scale) < 1e-6
    # Resume and Stop with robot 1 inspected, its beams drawn: the inspector's requests meet
    # the run's end without an error in the console (the page fixture checks)
    page.get_by_role("button", name="Resume").click()
    expect(page.get_by_role("button", name="Pause")).to_have_class("primary")
    page.wait_for_timeout(400)
    page.get_by_role("button", name="Stop").click()
    state = page.get_by_label("Live state")
    expect(state).to_contain_text("stopped at t = ")
    expect(state).to_contain_text("; recorded in runs/")
    assert "recording" not in state.text_content() and "finished" not in state.text_content()
    expect(page.locator("#message")).not_to_contain_text("starting")
    expect(page.get_by_role("link", name="Open the replay")).to_be_visible()
    page.wait_for_timeout(500)  # (requests in flight at the end come back)
    end = call(f"{url}/api/live/{run['id']}", "GET")
    recorded = load_run(root / end["run"])
    assert recorded.summary["status"] == "stopped"
    assert (recorded.events["kind"] == "edit").sum() == 2
    # the drag recorded at the millimetre (x = 5.003, not the screen's 5.0031782...)
    move = tomllib.loads((root / end["run"] / "scenario.toml").read_text())["edits"][0]
    assert move["kind"] == "move_robot"
    for value, meant in ((move["x"], 5.0), (move["y"], 4.5)):
        assert round(value, 3) == value and abs(value - meant) < 0.05
    # the Runs page lists the live run at the top
    page.goto(f"{url}/#/runs")
    expect(page.get_by_role("link", name=f"live {run['id']}:")).to_contain_text("finished")


def test_run_live_from_the_scenarios_page_a_battery_row_and_an_error_shown(
        page: Any, site: tuple[str, Path]) -> None:
    url, root = site
    (root / "maps").mkdir(exist_ok=True)
    save_map(Map.box(10.0, 6.0, name="room"), root / "maps" / "room.txt")
    call(f"{url}/api/scenarios/file", "PUT", scenario_body(settings={"time_limit": 60.0}))
    page.goto(f"{url}/#/scenarios")
    page.get_by_role("button", name="scenarios/two.toml").click()
    # the file's editor replaces the empty one once opened: act on it, not on the old one
    expect(page.get_by_role("status")).to_contain_text("opened scenarios/two.toml")
    page.get_by_label("Algorithm", exact=True).select_option("go_to_goal")
    page.get_by_role("button", name="Run live").click()
    expect(page).to_have_url(re.compile(r"#/live/\d+$"), timeout=120_000)
    expect(page.get_by_label("Live state")).to_contain_text("running")
    page.get_by_role("button", name="Stop").click()
    expect(page.get_by_label("Live state")).to_contain_text("stopped at t = ")
    # a battery's row: the same run again, live
    page.goto(f"{url}/#/batteries")
    fill_battery_form(page, "one", robots="2", seeds=1, runs=1)
    page.get_by_role("button", name="Start battery").click()
    expect(page.get_by_label("Progress", exact=True)).to_contain_text("1 of 1 runs finished",
                                                                      timeout=90_000)
    page.get_by_role("button", name="Run live: run 1").click()
    expect(page).to_have_url(re.compile(r"#/live/\d+$"), timeout=120_000)
    expect(page.get_by_label("Live state")).to_contain_text(
        "finished: the time limit was reached at t = 0.50 s")
    live_id = int(page.url.rsplit("/", 1)[1])
    ended = call(f"{url}/api/live/{live_id}", "GET")
    row = call(f"{url}/api/batteries/status?path=batteries/one", "GET")["runs"][0]
    assert (ended["scenario"], ended["seed"], ended["battery_run"]) == ("line", row["seed"], 1)
    assert load_run(root / ended["run"]).summary["robots"] == 2  # the row's parameters
    # an algorithm that raises: its error, as the CLI words it, on the page
    (root / "algorithms").mkdir(exist_ok=True)
    (root / "algorithms" / "raises.py").write_text(
        "def step(robot):\n    raise ValueError('no way forward')\n")
    run = call(f"{url}/api/live", "POST", {"scenario": "scenarios/two.toml",
                                           "algorithm": "algorithms/raises.py"})
    page.goto(f"{url}/#/live/{run['id']}")
    expect(page.get_by_role("alert")).to_contain_text(  # the file named as in the workspace
        "error: ValueError in robot 0 at t=0 s, algorithms/raises.py:2: no way forward")
    expect(page.get_by_label("Live state")).to_contain_text("ended in error")
