"""The inspector on the Runs page, the trajectories plot opened full size, and a built-in
scenario opened as a new file (Playwright, Debian's Chromium). Truth: the run's
trajectory.parquet and its robot log read directly, the catalog's scenario."""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq
from playwright import sync_api as playwright_api

from mimics.catalog import load_scenario
from mimics.records.run_folder import load_run
from mimics.world.scenario_files import load_scenario_toml
from tests.interfaces.web.browser import message, replay_pixels

expect = playwright_api.expect
RUN = "runs/line-go_to_goal-s1"


def open_run(page: Any, url: str) -> None:
    page.goto(f"{url}/#/runs?path={RUN}")
    expect(page.get_by_role("button", name="Play")).to_be_enabled()


def click_robot(page: Any, robot: int) -> None:
    """Click robot ``robot`` where the replay canvas shows it at the current frame."""
    px, py = page.evaluate(f"""() => {{
        const runs = window.workbench.runs;
        const at = (runs.frame * runs.data.robots + {robot}) * 3;
        return runs.view.toScreen(runs.data.poses[at], runs.data.poses[at + 1]);
    }}""")
    box = page.get_by_label("Replay canvas").bounding_box()
    page.mouse.click(box["x"] + px, box["y"] + py)


def field(page: Any, name: str) -> Any:
    return page.locator(f'[data-field="{name}"]')


def log_rows(text: str) -> list[list[str]]:
    """A robot log's table rows (after the units row), parsed by the csv module."""
    lines = text.splitlines()
    units = next(k for k, line in enumerate(lines) if line.startswith("[s];"))
    body = [line for line in lines[units + 1:] if line and not line.startswith("Deactivation")]
    return list(csv.reader(io.StringIO("\n".join(body)), delimiter=";"))


def test_a_clicked_robot_is_inspected_as_the_time_moves(page: Any,
                                                        site: tuple[str, Path]) -> None:
    url, root = site
    table = pq.read_table(root / RUN / "trajectory.parquet").to_pandas()
    log_text = load_run(root / RUN).log_path(1).read_text(encoding="utf-8")
    open_run(page, url)
    click_robot(page, 1)
    expect(field(page, "id")).to_have_text("1")
    expect(field(page, "type")).to_have_text("Pioneer3AT")
    expect(field(page, "state")).to_have_text("active")
    start = table[(table["step"] == 0) & (table["robot"] == 1)].iloc[0]
    expect(field(page, "x")).to_have_text(f"{start['x']:.3f} m")
    expect(field(page, "y")).to_have_text(f"{start['y']:.3f} m")
    scenario = load_run(root / RUN).scenario
    gx, gy = scenario.goals[1]
    expect(field(page, "goal_distance")).to_have_text(
        f"{np.hypot(gx - start['x'], gy - start['y']):.3f} m")
    log = page.get_by_role("log", name="Robot log")
    expect(log).to_contain_text("robot id = 1")
    assert len(log_rows(log.inner_text())) == 1  # t = 0: the first row only

    bar = page.get_by_label("Events on the time bar").bounding_box()
    page.mouse.click(bar["x"] + bar["width"] * 0.7, bar["y"] + bar["height"] / 2)
    frame = page.evaluate("window.workbench.runs.frame")
    assert 15 <= frame <= 25  # 70% of 3 s, give or take a pixel
    row = table[(table["step"] == frame) & (table["robot"] == 1)].iloc[0]
    expect(field(page, "x")).to_have_text(f"{row['x']:.3f} m")
    expect(field(page, "v")).to_have_text(f"{row['v']:.3f} m/s")
    expect(field(page, "v_ref")).to_have_text(f"{row['v_ref']:.3f} m/s")
    assert f"{row['x']:.3f}" != f"{start['x']:.3f}"  # it moved
    expected = [r for r in log_rows(log_text) if float(r[0]) <= row["time"] + 1e-9]
    assert len(expected) == frame + 1
    expect(log).to_contain_text(";".join(expected[-1]))
    assert log_rows(log.inner_text()) == expected  # up to now, not the whole file
    assert page.evaluate("""() => {  // scrolled to the latest line
        const box = document.querySelector('[aria-label="Robot log"]');
        return box.scrollTop + box.clientHeight >= box.scrollHeight - 2;
    }""")
    wide = "() => { const box = document.querySelector('[aria-label=\"Robot log\"]');" \
        " return box.scrollWidth > box.clientWidth + 1; }"
    assert page.evaluate(wide)  # a row is wider than the pane: scrolled sideways...
    page.get_by_label("Wrap log lines").check()
    assert not page.evaluate(wide)  # ...or wrapped


def test_the_beams_toggle_draws_every_robots_beams(page: Any, site: tuple[str, Path]) -> None:
    url, _root = site
    open_run(page, url)
    click_robot(page, 0)
    page.wait_for_function("window.workbench.runs.beams.length === 270")
    page.get_by_label("Every robot's beams").check()
    page.wait_for_function("window.workbench.runs.beams.length === 3 * 270")
    segment = page.evaluate("window.workbench.runs.beams[2 * 270 + 135]")  # robot 2's middle
    x, y = (segment[0] + segment[2]) / 2, (segment[1] + segment[3]) / 2
    page.wait_for_timeout(100)  # drawn at the next animation frame
    pixels = replay_pixels(page, x, y, size=5)
    assert any(r - g > 30 for r, g, _b in pixels), pixels  # the beams' red
    page.get_by_label("Every robot's beams").uncheck()
    page.wait_for_function("window.workbench.runs.beams.length === 270")


def test_the_trajectories_plot_opens_full_size(page: Any, site: tuple[str, Path]) -> None:
    url, _root = site
    open_run(page, url)
    page.get_by_role("button", name="Trajectories plot").click()
    thumbnail = page.get_by_role("img", name=f"trajectories of {RUN}")
    expect(thumbnail).to_be_visible()
    page.wait_for_function("document.querySelector('figure.thumbnail img').naturalWidth > 0")
    small = thumbnail.bounding_box()["width"]
    thumbnail.click()
    dialog = page.get_by_role("dialog", name="Plot")
    expect(dialog).to_be_visible()
    large = dialog.get_by_role("img").bounding_box()
    assert small < 300  # a thumbnail in the side panel...
    # ...shown as large as the 1280 x 800 window allows (the PNG is 1000 x 800 pixels)
    assert large["width"] > 800 and abs(large["width"] / large["height"] - 1000 / 800) < 0.01
    dialog.get_by_role("button", name="Close").click()
    expect(dialog).to_be_hidden()


def test_a_builtin_scenario_opens_as_a_new_file(page: Any, site: tuple[str, Path]) -> None:
    url, root = site
    page.goto(f"{url}/#/scenarios")
    page.get_by_label("Built-in scenario").select_option("corridor")
    page.get_by_role("button", name="Open built-in").click()
    truth = load_scenario("corridor")
    expect(message(page)).to_have_text("opened the built-in scenario corridor as "
                                       f"scenarios/corridor.toml (not saved yet): "
                                       f"{truth.robot_count} robots")
    expect(page.get_by_label("Save scenario as")).to_have_value("scenarios/corridor.toml")
    assert not (root / "scenarios" / "corridor.toml").exists()  # not saved yet
    page.get_by_role("button", name="Save scenario").click()
    expect(message(page)).to_have_text(f"saved scenarios/corridor.toml: "
                                       f"{truth.robot_count} robots")
    saved = load_scenario_toml(root / "scenarios" / "corridor.toml")
    np.testing.assert_array_equal(saved.stages[:, :3], truth.stages[:, :3])
    np.testing.assert_array_equal(saved.goals, truth.goals)
    np.testing.assert_array_equal(saved.map.segments, truth.map.segments)
