"""scenario.toml gives back exactly the scenario that was run, map included."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from mimics.records.scenario_record import read_scenario_record, write_scenario_record
from mimics.world.errors import MimicsError
from mimics.world.maps import Map
from mimics.world.scenario import Scenario, Settings
from mimics.world.scenario_files import scenario_from_toml_text

from .helpers import PROBE, SMALL


def mixed_scenario() -> Scenario:
    """Two types, goals and no goals, awkward floats, walls and non-default settings."""
    rng = np.random.default_rng(3)
    stages = np.column_stack([rng.uniform(1, 9, 6), rng.uniform(1, 9, 6),
                              rng.uniform(-math.pi, math.pi, 6), [0.0, 0.1, 0, 0, 0, 1e-7]])
    goals = np.array([[8.0, 8.0], [np.nan, np.nan], [0.1 + 0.2, 5.0], [np.nan, np.nan],
                      [2.0, 2.0], [1 / 3, 2 / 3]])
    world = Map.box(10.0, 10.0, name="room \"A\"").with_segments([(2.0, 2.0, 2.5, 7.123456789)])
    world = Map(world.segments, world.bounds, world.name, "stage:somewhere")
    return Scenario(map=world, types=(PROBE, SMALL), type_index=[0, 1, 1, 0, 1, 0],
                    stages=stages, goals=goals,
                    settings=Settings(dt=0.05, comm_range=3.5, deactivate_on_deadlock=False),
                    name="mixed", parameters={"robots": 6, "seed": np.int64(3), "skip": None,
                                              "spread": (1.0, 2.0)})


def test_the_record_gives_back_the_same_scenario(tmp_path: Path) -> None:
    original = mixed_scenario()
    path = tmp_path / "scenario.toml"
    run = {"seed": 7, "algorithm": "go_to_goal", "policy": "abort", "time_limit": 60.0,
           "wall_limit": None}
    write_scenario_record(path, original, run)
    back, info = read_scenario_record(path)
    assert info["seed"] == 7 and "wall_limit" not in info
    np.testing.assert_array_equal(back.stages, original.stages)
    np.testing.assert_array_equal(back.goals, original.goals)
    np.testing.assert_array_equal(back.type_index, original.type_index)
    assert back.types == original.types
    assert back.map == original.map and back.map.name == original.map.name
    assert back.map.source == "stage:somewhere"
    assert back.settings == original.settings and back.name == "mixed"
    assert back.parameters == {"robots": 6, "seed": 3, "spread": [1.0, 2.0]}


def test_the_robot_lines_byte_for_byte(tmp_path: Path) -> None:
    """The robots' lines as written by hand: shortest exact floats, -0.0 kept, a goal only
    for a robot that has one (the fast writer must not change a byte of the record); starts
    far past any map (1e16) are refused by the Scenario itself."""
    original = Scenario(map=Map.box(5.0, 5.0), types=(PROBE, SMALL), type_index=[1, 0],
                        stages=[[0.1 + 0.2, 1e-7, -0.0, 2.0], [4.0, 2.5e-05, math.pi, 0.0]],
                        goals=[[np.nan, np.nan], [1 / 3, 2.5]])
    write_scenario_record(tmp_path / "s.toml", original, {})
    lines = (tmp_path / "s.toml").read_text().splitlines()
    start = lines.index("robots = [")
    assert lines[start + 1:start + 4] == [
        f'  {{ type = "{SMALL.name}", x = 0.30000000000000004, y = 1e-07, yaw = -0.0, '
        "v = 2.0 },",
        f'  {{ type = "{PROBE.name}", x = 4.0, y = 2.5e-05, yaw = 3.141592653589793, v = 0.0, '
        "goal = [0.3333333333333333, 2.5] },",
        "]"]


def test_types_with_the_same_name_stay_apart(tmp_path: Path) -> None:
    from dataclasses import replace

    twin = replace(SMALL, name=PROBE.name)
    original = Scenario.from_matrix([[1, 1, 0, 0], [3, 3, 0, 0]], Map.box(5.0, 5.0),
                                    [PROBE, twin], type_index=[0, 1])
    write_scenario_record(tmp_path / "s.toml", original, {})
    back, _ = read_scenario_record(tmp_path / "s.toml")
    assert [t.name for t in back.types] == ["probe", "probe#2"]
    assert back.types[1].width == SMALL.width


def test_it_reads_as_a_declarative_scenario(tmp_path: Path) -> None:
    original = mixed_scenario()
    path = tmp_path / "scenario.toml"
    write_scenario_record(path, original, {"seed": 1})
    text = path.read_text()
    without_run = text[:text.index("[run]")] + text[text.index("[settings]"):]
    loaded = scenario_from_toml_text(without_run, path)
    np.testing.assert_array_equal(loaded.stages, original.stages)
    np.testing.assert_array_equal(loaded.goals, original.goals)
    assert loaded.map == original.map and loaded.settings == original.settings
    assert [loaded.robot_type(i) for i in range(6)] == [original.robot_type(i) for i in range(6)]


def test_a_file_that_is_not_a_record(tmp_path: Path) -> None:
    (tmp_path / "plain.toml").write_text('name = "x"\n')
    with pytest.raises(MimicsError, match="no \\[run\\] table"):
        read_scenario_record(tmp_path / "plain.toml")
    (tmp_path / "bad.toml").write_text('[run]\nseed = 1\n')
    with pytest.raises(MimicsError, match="malformed"):
        read_scenario_record(tmp_path / "bad.toml")
    with pytest.raises(MimicsError, match="cannot read"):
        read_scenario_record(tmp_path / "missing.toml")
