"""What the Scenarios page accepts: a goal offset that is not two numbers is refused at its
field, a goal off the map or in a wall is refused when placed, placement snaps to the grid
(Playwright, Debian's Chromium)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from playwright import sync_api as playwright_api

from tests.interfaces.web.browser import click_world, message

expect = playwright_api.expect


def open_room(page: Any, site: tuple[str, Path]) -> None:
    url, root = site
    (root / "maps").mkdir(exist_ok=True)
    (root / "maps" / "box.txt").write_text("bounds 0 0 12 8\n0 0 12 0\n0 8 12 8\n")
    page.goto(f"{url}/#/scenarios")
    page.get_by_label("Map", exact=True).select_option("maps/box.txt")
    expect(page.get_by_text("0 robots on maps/box.txt")).to_be_visible()


def robots(page: Any) -> list[dict[str, Any]]:
    return page.evaluate("window.workbench.scenarios.robots")


def test_a_goal_offset_that_is_not_two_numbers_is_refused_at_the_field(
        page: Any, site: tuple[str, Path]) -> None:
    open_room(page, site)
    offset = page.get_by_label("Goal offset dx, dy (m)")
    problem = page.locator("#offset-problem")
    page.get_by_role("button", name="Line").click()
    for text in ("abc", "14 0", "1, 2, 3", "5,"):
        offset.fill(text)
        expect(offset).to_have_attribute("aria-invalid", "true")
        expect(problem).to_have_text("Type two numbers separated by a comma, such as 5, 0 "
                                     "(0, 0: robots without goals).")
        click_world(page, "scenarios", 2.0, 2.0)
        expect(message(page)).to_have_text("goal offset: not two numbers")
        assert robots(page) == []  # nothing placed, no goal silently dropped
    offset.fill(" 4 , -1.5 ")
    expect(problem).to_have_text("")
    expect(offset).not_to_have_attribute("aria-invalid", "true")
    page.get_by_label("Count", exact=True).fill("2")
    click_world(page, "scenarios", 2.0, 2.0)
    click_world(page, "scenarios", 2.0, 5.0)
    assert [r["goal"] for r in robots(page)] == [[6.0, 0.5], [6.0, 3.5]]
    offset.fill("0, 0")  # robots without goals, on purpose
    page.get_by_role("button", name="Remove all").click()
    click_world(page, "scenarios", 3.0, 2.0)
    click_world(page, "scenarios", 3.0, 5.0)
    assert [r["goal"] for r in robots(page)] == [None, None]


def test_goals_off_the_map_or_in_a_wall_are_refused_and_clicks_snap(
        page: Any, site: tuple[str, Path]) -> None:
    open_room(page, site)
    page.get_by_role("button", name="One").click()
    click_world(page, "scenarios", 2.1, 1.4)  # snapped to the 0.5 m grid: (2, 1.5)
    click_world(page, "scenarios", 6.0, 0.1)  # on the south wall
    expect(message(page)).to_have_text(
        "goal (6.00, 0.00) is in a wall (a robot there would touch it): not placed")
    assert robots(page) == []
    click_world(page, "scenarios", 6.1, 8.6)  # beyond the north bound
    expect(message(page)).to_have_text(
        "goal (6.00, 8.50) is off the map (0 to 12, 0 to 8): not placed")
    click_world(page, "scenarios", 9.9, 4.1)
    [robot] = robots(page)
    assert (robot["x"], robot["y"], robot["goal"]) == (2.0, 1.5, [10.0, 4.0])
    page.get_by_role("button", name="Line").click()
    page.get_by_label("Goal offset dx, dy (m)").fill("0, -4")
    page.get_by_label("Count", exact=True).fill("3")
    click_world(page, "scenarios", 4.0, 2.0)
    click_world(page, "scenarios", 8.0, 2.0)
    expect(message(page)).to_have_text(
        "goal (4.00, -2.00) is off the map (0 to 12, 0 to 8): not placed "
        "(and 2 more goals): no robot placed")
    assert len(robots(page)) == 1
    page.get_by_label("Snap to grid").uncheck()
    page.get_by_label("Goal offset dx, dy (m)").fill("0, 3")
    page.get_by_label("Count", exact=True).fill("1")
    click_world(page, "scenarios", 4.1, 2.2)
    click_world(page, "scenarios", 4.1, 2.2)
    added = robots(page)[1]
    assert abs(added["x"] - 4.1) < 0.05 and abs(added["y"] - 2.2) < 0.05  # not snapped


def test_robots_and_walls_can_be_typed(page: Any, site: tuple[str, Path]) -> None:
    url, _root = site
    open_room(page, site)
    start = page.get_by_label("Start x, y[, yaw] (m, rad)")
    goal = page.get_by_label("Goal gx, gy (m)")
    add = page.get_by_role("button", name="Add robot")
    start.fill("2.25, 3.1")
    goal.fill("9.5, 3.1")
    add.click()
    start.fill("4, 6, 1.5")
    goal.fill("")
    add.click()
    assert robots(page)[0]["x"] == 2.25 and robots(page)[0]["goal"] == [9.5, 3.1]
    assert robots(page)[0]["yaw"] == 0
    assert robots(page)[1] == {**robots(page)[1], "x": 4, "y": 6, "yaw": 1.5, "goal": None}
    start.fill("14 0")
    add.click()
    expect(message(page)).to_have_text("typed start: expected x, y or x, y, yaw (numbers)")
    start.fill("3, 3")
    goal.fill("30, 3")
    add.click()
    expect(message(page)).to_have_text(
        "goal (30.00, 3.00) is off the map (0 to 12, 0 to 8): not placed")
    assert len(robots(page)) == 2
    page.goto(f"{url}/#/maps")
    page.get_by_role("button", name="New map").click()
    wall = page.get_by_label("Wall x1, y1, x2, y2 (m)")
    wall.fill("1.05, 2, 7.3, 2")
    page.get_by_role("button", name="Add wall").click()
    wall.fill("1, 2, 3")
    page.get_by_role("button", name="Add wall").click()
    expect(message(page)).to_have_text("typed wall: expected x1, y1, x2, y2 (four numbers)")
    assert page.evaluate("window.workbench.maps.segments") == [[1.05, 2, 7.3, 2]]
