"""The page never drops work silently: saving over another file asks, unsaved edits are
asked about before they are replaced or the tab is reloaded (Playwright, Debian's Chromium)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import pytest
from playwright import sync_api as playwright_api

from mimics.world.map_files import load_map
from tests.interfaces.web.browser import click_world, message

expect = playwright_api.expect


def draw_segment(page: Any, start: tuple[float, float], end: tuple[float, float]) -> None:
    page.get_by_role("button", name="Segment").click()
    click_world(page, "maps", *start)
    click_world(page, "maps", *end)


def test_saving_over_another_map_asks_and_a_no_keeps_it(page: Any, site: tuple[str, Path]
                                                        ) -> None:
    url, root = site
    (root / "maps").mkdir(exist_ok=True)
    (root / "maps" / "kept.txt").write_text("bounds 0 0 10 10\n0 0 10 0\n")
    questions: list[str] = []
    answer = {"yes": False}

    def on_dialog(dialog: Any) -> None:
        questions.append(dialog.message)
        dialog.accept() if answer["yes"] else dialog.dismiss()

    page.on("dialog", on_dialog)
    page.goto(f"{url}/#/maps")
    page.get_by_role("button", name="New map").click()
    draw_segment(page, (1.0, 1.0), (6.0, 1.0))
    page.get_by_label("Save as").fill("maps/kept.txt")
    page.get_by_role("button", name="Save map").click()
    expect(message(page)).to_have_text(
        "not saved: maps/kept.txt exists already (choose another file name)")
    assert questions == ["maps/kept.txt exists already. Replace it?"]
    assert load_map(root / "maps" / "kept.txt").segments.tolist() == [[0, 0, 10, 0]]
    answer["yes"] = True
    page.get_by_role("button", name="Save map").click()
    expect(message(page)).to_have_text("saved maps/kept.txt: 1 walls")
    assert load_map(root / "maps" / "kept.txt").segments.tolist() == [[1, 1, 6, 1]]
    draw_segment(page, (2.0, 3.0), (2.0, 8.0))  # the file is this map's own now: no question
    page.get_by_role("button", name="Save map").click()
    expect(message(page)).to_have_text("saved maps/kept.txt: 2 walls")
    assert len(questions) == 2


def test_unsaved_edits_are_asked_about_before_they_are_lost(page: Any, site: tuple[str, Path]
                                                            ) -> None:
    url, root = site
    (root / "maps").mkdir(exist_ok=True)
    (root / "maps" / "other.txt").write_text("bounds 0 0 10 10\n0 0 10 0\n0 10 10 10\n")
    dialogs: list[tuple[str, str]] = []
    page.on("dialog", lambda d: (dialogs.append((d.type, d.message)), d.dismiss()))
    page.goto(f"{url}/#/maps")
    page.get_by_role("button", name="New map").click()
    draw_segment(page, (1.0, 1.0), (6.0, 1.0))
    page.get_by_role("button", name="maps/other.txt").click()  # refused: the edits stay
    assert dialogs == [("confirm", "Unsaved edits to this map will be lost. Continue?")]
    expect(page.get_by_label("Wall count")).to_have_text("1 walls")
    page.get_by_role("link", name="Scenarios").click()  # other pages keep this one's edits
    page.get_by_role("link", name="Maps").click()
    expect(page.get_by_label("Wall count")).to_have_text("1 walls")
    assert len(dialogs) == 1
    with pytest.raises(playwright_api.Error, match="ERR_ABORTED"):  # leaving the workbench:
        page.goto("about:blank")  # the browser's own question, answered "stay"
    assert [kind for kind, _ in dialogs] == ["confirm", "beforeunload"]
    expect(page.get_by_label("Wall count")).to_have_text("1 walls")  # the edits stay


def test_a_saved_map_is_left_without_a_question(page: Any, site: tuple[str, Path]) -> None:
    url, _root = site
    dialogs: list[str] = []
    page.on("dialog", lambda d: (dialogs.append(d.type), d.dismiss()))
    page.goto(f"{url}/#/maps")
    page.get_by_role("button", name="New map").click()
    draw_segment(page, (1.0, 1.0), (6.0, 1.0))
    page.get_by_label("Save as").fill("maps/fresh.txt")
    page.get_by_role("button", name="Save map").click()
    expect(message(page)).to_have_text("saved maps/fresh.txt: 1 walls")
    page.get_by_role("button", name="maps/fresh.txt").click()
    expect(message(page)).to_have_text("opened maps/fresh.txt: 1 walls")
    page.reload()
    assert dialogs == []


def test_saving_a_scenario_over_another_asks_and_its_own_file_does_not(
        page: Any, site: tuple[str, Path]) -> None:
    url, root = site
    (root / "maps").mkdir(exist_ok=True)
    (root / "maps" / "yard.txt").write_text("bounds 0 0 12 8\n0 0 12 0\n0 8 12 8\n")
    (root / "scenarios").mkdir(exist_ok=True)
    (root / "scenarios" / "taken.toml").write_text("# someone's scenario\n")
    questions: list[str] = []
    page.on("dialog", lambda d: (questions.append(d.message), d.dismiss()))
    page.goto(f"{url}/#/scenarios")
    page.get_by_label("Map", exact=True).select_option("maps/yard.txt")
    page.get_by_role("button", name="One").click()
    click_world(page, "scenarios", 2.0, 4.0)
    click_world(page, "scenarios", 8.0, 4.0)
    page.get_by_label("Save scenario as").fill("scenarios/taken.toml")
    page.get_by_role("button", name="Save scenario").click()
    expect(message(page)).to_have_text(
        "not saved: scenarios/taken.toml exists already (choose another file name)")
    assert questions == ["scenarios/taken.toml exists already. Replace it?"]
    assert (root / "scenarios" / "taken.toml").read_text() == "# someone's scenario\n"
    page.get_by_label("Save scenario as").fill("scenarios/mine.toml")
    page.get_by_role("button", name="Save scenario").click()
    expect(message(page)).to_have_text("saved scenarios/mine.toml: 1 robots")
    click_world(page, "scenarios", 2.0, 6.0)
    click_world(page, "scenarios", 8.0, 6.0)
    page.get_by_role("button", name="Save scenario").click()  # its own file: no question
    expect(message(page)).to_have_text("saved scenarios/mine.toml: 2 robots")
    assert len(questions) == 1
