"""The built-in robot types: usable by name in scenario files, the e-puck's explicit beams,
the TOML form of explicit beam angles, and even fans left as they were."""

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from mimics.engine.simulation import Simulation
from mimics.records.runner import prepare
from mimics.world.errors import ScenarioError
from mimics.world.maps import Map
from mimics.world.robot_types import (
    BUILTIN_ROBOT_TYPES,
    EPUCK,
    PIONEER_3AT,
    RangerSpec,
    builtin_robot_type,
    robot_type_from_dict,
)
from mimics.world.scenario import Scenario
from mimics.world.scenario_files import load_scenario_toml, save_scenario_toml

SCENARIO = """\
name = "one {name}"
map = {{ segments = [[-1.0, -1.0, 4.0, -1.0], [4.0, -1.0, 4.0, 1.0]], bounds = [-2, -2, 5, 2] }}

[[robots]]
type = "{name}"
x = 0.0
y = 0.0
goal = [{goal}, 0.0]

[settings]
time_limit = 30.0
"""


@pytest.mark.parametrize("name", list(BUILTIN_ROBOT_TYPES))
def test_each_builtin_type_runs_by_name_from_a_toml_scenario(name: str, tmp_path: Path) -> None:
    robot_type = BUILTIN_ROBOT_TYPES[name]
    goal = 0.5 + 6 * robot_type.kv  # about 6 s of driving at full speed
    path = tmp_path / "one.toml"
    path.write_text(SCENARIO.format(name=name, goal=min(goal, 3.0)))
    scenario = load_scenario_toml(path)
    assert scenario.robot_type(0) == robot_type
    result = prepare(path, "go_to_goal", seed=0).run()
    assert result.reached_goal == 1 and result.collisions == 0
    # written back, the built-in type is referred to by name and reads back equal
    again = load_scenario_toml(save_scenario_toml(scenario, tmp_path / "again.toml"))
    assert again.robot_type(0) == robot_type
    assert "[types" not in (tmp_path / "again.toml").read_text()


def test_epuck_infrared_beams_read_the_walls_along_their_own_directions() -> None:
    """An e-puck in the middle of a 0.17 m box: a beam at angle a meets a wall at
    0.085 / max(|cos a|, |sin a|); within 0.1 m it reads that, else the range."""
    half = 0.085
    box = [(-half, -half, half, -half), (half, -half, half, half), (half, half, -half, half),
           (-half, half, -half, -half)]
    quiet = replace(EPUCK, ranger=replace(EPUCK.ranger, sigma=0.0))
    scenario = Scenario.from_matrix([[0.0, 0.0, 0.1, 0.0, np.nan, np.nan]],
                                    Map(np.array(box, dtype=float), (-1, -1, 1, 1)), quiet)
    sim = Simulation(scenario, lambda robot: (0.0, 0.1), time_limit=0.1)
    sim.start()
    angles = np.radians([-142, -90, -45, -18, 18, 45, 90, 142])
    np.testing.assert_array_equal(sim.types.beam_offsets[0], angles)
    world = angles + 0.1
    wall = half / np.maximum(np.abs(np.cos(world)), np.abs(np.sin(world)))
    expected = np.where(wall <= 0.1, wall, 0.1)
    assert 0 < np.sum(wall <= 0.1) < 8  # some beams hit, some do not
    np.testing.assert_allclose(sim.state.scan[0], expected, rtol=1e-12, atol=1e-12)


def test_explicit_beam_angles_round_trip_through_the_toml_form() -> None:
    data = EPUCK.to_dict()
    assert data["ranger"]["angles"] == list(EPUCK.ranger.angles)
    assert robot_type_from_dict(data) == EPUCK
    assert "angles" not in PIONEER_3AT.to_dict()["ranger"]  # even fans: as before
    custom = robot_type_from_dict({"name": "Five", "base": "e-puck",
                                   "ranger": {"beams": 3, "angles": [-1.0, 0.0, 1.0]}})
    assert custom.ranger.beam_offsets() == (-1.0, 0.0, 1.0)


@pytest.mark.parametrize("angles", [[0.0, 1.0], [1.0, 0.0, 2.0], [0.0, 1.0, 4.0]])
def test_bad_beam_angles_are_one_clear_error(angles: list[float]) -> None:
    with pytest.raises(ScenarioError, match=r"ranger angles must be 3 increasing angles"):
        robot_type_from_dict({"name": "Bad", "base": "e-puck",
                              "ranger": {"beams": 3, "angles": angles}})


@pytest.mark.parametrize("fov_degrees, beams", [(270, 270), (180, 180), (360, 360), (58, 58)])
def test_even_fans_are_spread_as_before(fov_degrees: float, beams: int) -> None:
    fov = math.radians(fov_degrees)
    full = math.isclose(fov, 2 * math.pi)
    step = fov / beams if full else fov / (beams - 1)
    spec = RangerSpec(fov=fov, beams=beams, range=1.0)
    assert spec.beam_offsets() == tuple(-fov / 2 + i * step for i in range(beams))


def test_type_names_are_found_exactly_or_ignoring_case() -> None:
    assert builtin_robot_type("kobuki") is BUILTIN_ROBOT_TYPES["Kobuki"]
    assert builtin_robot_type("e-puck") is EPUCK
    with pytest.raises(ScenarioError, match=r"unknown robot type 'Roomba' \(expected one of "
                                            r"Pioneer3AT, .*point\)"):
        builtin_robot_type("Roomba")


def test_published_figures_of_the_new_types() -> None:
    """Dimensions and limits as the makers publish them (see the types' docstrings)."""
    burger, kobuki = BUILTIN_ROBOT_TYPES["TurtleBot3Burger"], BUILTIN_ROBOT_TYPES["Kobuki"]
    assert (burger.length, burger.width, burger.kv, burger.kw) == (0.138, 0.178, 0.22, 2.84)
    assert (burger.ranger.beams, burger.ranger.range) == (360, 3.5)
    assert burger.ranger.beam_offsets()[1] - burger.ranger.beam_offsets()[0] == pytest.approx(
        math.radians(1))
    assert (kobuki.kv, kobuki.kw, kobuki.width) == (0.7, math.pi, 0.3515)
    assert EPUCK.kv == pytest.approx(0.128, abs=0.001)  # 1000 steps/s, 41 mm wheels
    assert EPUCK.kw == pytest.approx(2 * EPUCK.kv / 0.053)
    assert EPUCK.ranger.beams == 8
