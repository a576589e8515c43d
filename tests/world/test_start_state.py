"""Robots that start overlapping each other or a wall, or outside the map, are reported when
the scenario loads (which robots, where), unless the user keeps them on purpose."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import shapely

import mimics.world.start_state as start_state
from mimics.catalog import load_scenario
from mimics.world.errors import ScenarioError
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX
from mimics.world.scenario import Scenario, Settings
from mimics.world.scenario_files import load_scenario_toml
from mimics.world.start_state import Bodies, overlapping_robots, validate_scenario

ROOM = Map.box(10.0, 6.0)


def crowded(settings: Settings | None = None) -> Scenario:
    """Robots 0-1 overlap, robot 2 touches the south wall, robot 3 is outside, robot 4 is fine."""
    rows = [[2.0, 2.0, 0, 0], [2.1, 2.0, 0, 0], [5.0, 0.05, 0, 0], [20.0, 3.0, 0, 0],
            [8.0, 4.0, 0, 0]]
    return Scenario.from_matrix(rows, ROOM, PIONEER_2DX, settings=settings, name="crowded")


def test_every_start_problem_is_named_with_its_position_in_one_line() -> None:
    with pytest.raises(ScenarioError) as info:
        validate_scenario(crowded(), "crowded.py")
    message = str(info.value)
    assert "\n" not in message
    assert "robot 3: start (20, 3) is outside the map bounds (0, 0, 10, 6)" in message
    assert "robot 2: robot at (5, 0.05) touches wall 0" in message
    assert "robot 0 at (2, 2) and robot 1 at (2.1, 2) overlap" in message
    assert "(3 start problem(s); keep them on purpose with --allow-overlap" in message
    assert "robot 4" not in message


def test_allow_overlap_keeps_them_and_returns_what_was_kept() -> None:
    kept = validate_scenario(crowded(), allow_overlap=True)
    assert len(kept) == 3
    assert validate_scenario(crowded(Settings(allow_overlap=True))) == kept


def test_long_lists_are_cut_with_a_count() -> None:
    rows = [[1.0 + 0.05 * i, 3.0, 0, 0] for i in range(12)]
    scenario = Scenario.from_matrix(rows, ROOM, PIONEER_2DX)
    with pytest.raises(ScenarioError, match=r"and \d+ more \(\d+ start problem"):
        validate_scenario(scenario)


def test_python_scenarios_are_checked_when_they_load(tmp_path: Path) -> None:
    path = tmp_path / "pile.py"
    path.write_text(
        "from mimics.world.maps import Map\nfrom mimics.world.scenario import Scenario\n"
        "from mimics.world.robot_types import PIONEER_2DX\n"
        "def scenario(gap=0.1):\n"
        "    rows = [[1.0 + gap * i, 1.0, 0.0, 0.0] for i in range(3)]\n"
        "    return Scenario.from_matrix(rows, Map.empty((-5, -5, 5, 5)), PIONEER_2DX)\n")
    with pytest.raises(ScenarioError, match=r"scenario 'pile': robot 0 at \(1, 1\) and robot 1"):
        load_scenario(path)
    assert load_scenario(path, allow_overlap=True).robot_count == 3
    assert load_scenario(path, gap=1.0).robot_count == 3


def test_toml_scenarios_keep_overlaps_with_the_setting_or_the_flag(tmp_path: Path) -> None:
    robots = ('[[robots]]\ntype = "Pioneer2DX"\nx = 2.0\ny = 2.0\n'
              '[[robots]]\ntype = "Pioneer2DX"\nx = 2.1\ny = 2.0\n')
    text = 'map = { segments = [], bounds = [0.0, 0.0, 10.0, 6.0] }\n' + robots
    path = tmp_path / "pair.toml"
    path.write_text(text)
    with pytest.raises(ScenarioError, match=r"robots\[0\] \(line 2\) at \(2, 2\) and robots\[1\]"):
        load_scenario_toml(path)
    assert load_scenario(str(path), allow_overlap=True).robot_count == 2
    path.write_text(text + "[settings]\nallow_overlap = true\n")
    assert load_scenario_toml(path).settings.allow_overlap


def rectangle(bodies: Bodies, i: int) -> shapely.Polygon:
    c, s = np.cos(bodies.headings[i]), np.sin(bodies.headings[i])
    hl, hw = bodies.half_length[i], bodies.half_width[i]
    local = np.array([[hl, hw], [-hl, hw], [-hl, -hw], [hl, -hw]])
    return shapely.Polygon(bodies.centers[i] + local @ np.array([[c, s], [-s, c]]))


def shapely_pairs(bodies: Bodies) -> set[tuple[int, int]]:
    """Touching pairs by shapely over every pair (the independent reference)."""
    shapes = [rectangle(bodies, i) for i in range(len(bodies.centers))]
    return {(i, j) for i in range(len(shapes)) for j in range(i + 1, len(shapes))
            if shapes[i].intersects(shapes[j])}


def test_the_sweep_in_chunks_finds_the_same_pairs_as_every_pair(
        monkeypatch: pytest.MonkeyPatch) -> None:
    rng = np.random.default_rng(3)
    bodies = Bodies(rng.uniform(0, 6, (120, 2)), rng.uniform(-np.pi, np.pi, 120),
                    rng.uniform(0.05, 0.4, 120), rng.uniform(0.05, 0.3, 120))
    monkeypatch.setattr(start_state, "PAIR_CHUNK", 7)  # many chunks
    first, second = overlapping_robots(bodies)
    found = set(zip(first.tolist(), second.tolist(), strict=True))
    assert found == shapely_pairs(bodies)
    assert len(found) > 20


def test_a_long_line_on_one_axis_is_swept_along_it() -> None:
    # 200 000 robots on the y-axis share x: a sweep along x would list 2e10 pairs
    n = 200_000
    centers = np.column_stack([np.zeros(n), np.arange(n, dtype=float)])
    bodies = Bodies(centers, np.zeros(n), np.full(n, 0.35), np.full(n, 0.25))
    first, _ = overlapping_robots(bodies)
    assert first.size == 0


def test_the_python_api_refuses_or_keeps_such_starts() -> None:
    import mimics

    with pytest.raises(ScenarioError, match="overlap at the start"):
        mimics.simulate(crowded(), "go_to_goal", time=0.2)
    result = mimics.simulate(crowded(), "go_to_goal", time=0.2, allow_overlap=True)
    assert result.collisions == 3  # the pair and the robot on the wall, at time zero
