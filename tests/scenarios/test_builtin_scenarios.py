"""Every built-in scenario builds, starts in free space, and the Stage ones match Stage."""

import imageio.v3 as iio
import numpy as np
import pytest

from mimics.catalog import list_scenarios, load_scenario
from mimics.engine.collision import Bodies, find_collisions
from mimics.engine.robot_index import build_robot_index
from mimics.engine.spatial_index import build_segment_grid
from mimics.world.errors import ScenarioError
from mimics.world.robot_types import PIONEER_2DX, SWARMBOT
from mimics.world.scenario import Scenario
from mimics.world.scenario_files import validate_scenario
from tests.stage import stage_file

NAMES = [name for name, _ in list_scenarios()]


def needs_stage() -> None:
    stage_file("cave_filled.png")


def engine_contacts(scenario: Scenario) -> np.ndarray:
    """Robots the engine's exact collision check finds touching something at the start."""
    sizes = np.array([(t.length / 2, t.width / 2) for t in scenario.types])[scenario.type_index]
    bodies = Bodies(np.ascontiguousarray(scenario.stages[:, :2]),
                    np.ascontiguousarray(scenario.stages[:, 2]), sizes[:, 0].copy(),
                    sizes[:, 1].copy())
    solid = np.ones(scenario.robot_count, dtype=bool)
    walls = build_segment_grid(scenario.map.segments, scenario.map.bounds)
    robots = build_robot_index(*bodies, solid)
    with_whom, _ = find_collisions(bodies, solid, solid, walls, robots)
    return np.flatnonzero(with_whom != -2)


@pytest.mark.parametrize("name", NAMES)
def test_every_builtin_builds_with_no_initial_overlap(name: str) -> None:
    if name in ("cave", "hospital"):
        needs_stage()
    scenario = load_scenario(name)
    assert scenario.robot_count >= 1
    assert scenario.settings.dt == 0.1
    validate_scenario(scenario, name)
    assert engine_contacts(scenario).size == 0


def test_the_teaching_scenarios_describe_themselves() -> None:
    described = dict(list_scenarios())
    for name in ("cave", "hospital", "corridor", "circle_swap", "obstacle_room"):
        assert described[name] and "\n" not in described[name]


def test_cave_has_100_pioneers_on_free_pixels() -> None:
    needs_stage()
    cave = load_scenario("cave")
    assert cave.robot_count == 100 and cave.types == (PIONEER_2DX,)
    assert cave.map.bounds == (-8.0, -8.0, 8.0, 8.0)
    assert not cave.has_goal.any()
    assert cave.settings.time_limit == 600.0
    image = iio.imread(stage_file("cave_filled.png"))
    rows, cols = image.shape
    x, y = cave.stages[:, 0], cave.stages[:, 1]
    col = np.floor((x + 8.0) / 16.0 * cols).astype(int)
    row = np.floor((8.0 - y) / 16.0 * rows).astype(int)  # the image's top row is north
    assert (image[row, col] > 127).all()
    assert load_scenario("cave", robots=10).robot_count == 10
    assert np.array_equal(load_scenario("cave", robots=10).stages, cave.stages[:10])
    with pytest.raises(ScenarioError, match="from 1 to 100"):
        load_scenario("cave", robots=101)


def test_hospital_has_2000_swarmbots_in_two_blocks() -> None:
    needs_stage()
    hospital = load_scenario("hospital", fixed=True)  # Stage's poses exactly
    assert hospital.robot_count == 2000 and hospital.types == (SWARMBOT,)
    assert hospital.map.bounds == pytest.approx((-70.0, -29.5, 70.0, 30.5))
    x, y = hospital.stages[:, 0], hospital.stages[:, 1]
    assert (x[:1000] <= -9.25).all() and (x[1000:] >= 0.0).all()
    assert set(np.round(y, 2).tolist()) == {-15.0, -14.75, -14.5, -14.25, -14.0}
    assert load_scenario("hospital", robots=1000, fixed=True).stages[:, 0].max() == \
        pytest.approx(-9.25)
    jittered = load_scenario("hospital", run_seed=3).stages  # the run's seed moves each start
    assert 0 < np.abs(jittered[:, :2] - hospital.stages[:, :2]).max() <= 0.02


def test_teaching_scenarios_take_their_parameters() -> None:
    corridor = load_scenario("corridor", robots=12)
    assert corridor.robot_count == 12 and corridor.has_goal.all()
    west = corridor.stages[:, 0] < 8.0
    assert west.sum() == 6 and (corridor.goals[west, 0] > 8.0).all()
    swap = load_scenario("circle_swap", robots=10, radius=5.0, fixed=True)
    assert np.allclose(swap.goals, -swap.stages[:, :2])
    jittered = load_scenario("circle_swap", robots=10, radius=5.0, run_seed=2)
    assert np.array_equal(jittered.goals, swap.goals)
    assert 0 < np.abs(jittered.stages[:, :2] - swap.stages[:, :2]).max() <= 0.1
    room = load_scenario("obstacle_room", robots=20, seed=4)
    assert room.robot_count == 20 and not room.has_goal.any()
    assert not np.array_equal(room.stages, load_scenario("obstacle_room", robots=20).stages)
    with pytest.raises(ScenarioError, match="too close"):
        load_scenario("circle_swap", robots=60, radius=1.0)
