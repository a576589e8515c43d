"""Declarative TOML scenarios: generators, overrides, a lossless round trip, strict errors."""

from pathlib import Path

import numpy as np
import pytest
import shapely

from mimics.engine.collision import Bodies as EngineBodies
from mimics.engine.collision import find_collisions
from mimics.engine.robot_index import build_robot_index
from mimics.engine.spatial_index import build_segment_grid
from mimics.world.errors import ScenarioError
from mimics.world.map_files import save_map
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX, PIONEER_3AT
from mimics.world.scenario import Scenario, Settings
from mimics.world.scenario_files import (
    Bodies,
    load_scenario_toml,
    overlapping_robots,
    random_placement,
    save_scenario_toml,
    scenario_toml_parameters,
    touching_walls,
    validate_scenario,
)
from tests.file_errors import file_error
from tests.toml_text import toml_text

ROOM = 'map = { segments = [[0.0, 0.0, 10.0, 0.0], [0.0, 6.0, 10.0, 6.0]], ' \
       'bounds = [-1.0, -1.0, 11.0, 7.0] }\n'

FULL = ROOM + toml_text({
    "name": "demo", "description": "every kind of robot entry",
    "robots": [
        {"type": "Pioneer2DX", "x": 1.0, "y": 1.0, "yaw": 0.5, "goal": [8.0, 1.0]},
        {"generator": "line", "type": "Small", "count": 4, "start": [1.0, 2.0],
         "step": [0.6, 0.0], "goal_offset": [7.0, 0.0]},
        {"generator": "grid", "type": "Pioneer3AT", "rows": 2, "columns": 3,
         "origin": [5.0, 3.0], "spacing": [1.0, 1.2]},
        {"generator": "random", "type": "Pioneer2DX", "count": 5, "seed": 3,
         "region": [0.5, 0.5, 9.5, 5.5], "goal_region": [0.5, 0.5, 9.5, 5.5]}],
    "types": {"Small": {"base": "Pioneer2DX", "width": 0.2, "ranger": {"beams": 90}}},
    "settings": {"time_limit": 120.0, "comm_range": 5.0}})


def write(tmp_path: Path, text: str, name: str = "scenario.toml") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def same(a: Scenario, b: Scenario) -> bool:
    return (a.map == b.map and a.map.name == b.map.name and a.settings == b.settings
            and a.name == b.name and np.array_equal(a.stages, b.stages)
            and np.array_equal(a.goals, b.goals, equal_nan=True)
            and [a.robot_type(i) for i in range(a.robot_count)]
            == [b.robot_type(i) for i in range(b.robot_count)])


def test_every_kind_of_robot_entry(tmp_path: Path) -> None:
    s = load_scenario_toml(write(tmp_path, FULL))
    assert s.name == "demo" and s.robot_count == 1 + 4 + 6 + 5
    assert s.stages[0].tolist() == [1.0, 1.0, 0.5, 0.0]
    assert s.goals[0].tolist() == [8.0, 1.0]
    assert np.allclose(s.stages[1:5, :2], [[1.0, 2.0], [1.6, 2.0], [2.2, 2.0], [2.8, 2.0]])
    assert np.allclose(s.goals[1:5], s.stages[1:5, :2] + [7.0, 0.0])
    small = s.robot_type(1)
    assert (small.name, small.width, small.ranger.beams, small.ranger.range) == (
        "Small", 0.2, 90, 8.0)
    assert np.allclose(s.stages[5:11, :2], [[5, 3], [6, 3], [7, 3], [5, 4.2], [6, 4.2], [7, 4.2]])
    assert s.robot_type(5) == PIONEER_3AT
    assert not s.has_goal[5:11].any() and s.has_goal[11:].all()
    assert s.settings == Settings(time_limit=120.0, comm_range=5.0)
    again = load_scenario_toml(tmp_path / "scenario.toml")
    assert same(s, again)  # seeded: the random robots are the same every time


def test_parameters_override_robots_seed_and_settings(tmp_path: Path) -> None:
    path = write(tmp_path, FULL)
    s = load_scenario_toml(path, robots=3, dt=0.05)
    assert s.robot_count == 3 and s.settings.dt == 0.05
    assert s.parameters == {"robots": 3, "dt": 0.05}
    seeded = load_scenario_toml(path, seed=11)
    assert not np.array_equal(seeded.stages[11:], load_scenario_toml(path).stages[11:])
    params = scenario_toml_parameters(path)
    assert params["robots"] == 16 and params["time_limit"] == 120.0 and "seed" in params
    with pytest.raises(ScenarioError, match="no parameter 'speed'"):
        load_scenario_toml(path, speed=2)
    with pytest.raises(ScenarioError, match="robots: 40 asked, but the file defines 16"):
        load_scenario_toml(path, robots=40)
    with pytest.raises(ScenarioError, match="parameter dt: expected a positive number"):
        load_scenario_toml(path, dt=-1.0)


def test_round_trip_is_lossless(tmp_path: Path) -> None:
    original = load_scenario_toml(write(tmp_path, FULL))
    saved = save_scenario_toml(original, tmp_path / "saved.toml")
    assert same(original, load_scenario_toml(saved))
    with_file = save_scenario_toml(original, tmp_path / "with_file.toml", map_file="walls.txt")
    assert 'map = { file = "walls.txt"' in with_file.read_text()
    assert same(original, load_scenario_toml(with_file))


def test_python_scenario_round_trip(tmp_path: Path) -> None:
    from mimics.scenarios.circle_swap import scenario

    original = scenario(robots=6)
    assert same(original, load_scenario_toml(save_scenario_toml(original, tmp_path / "c.toml")))


def test_map_from_a_file_relative_to_the_scenario(tmp_path: Path) -> None:
    (tmp_path / "maps").mkdir()
    save_map(Map.box(10.0, 6.0, name="box"), tmp_path / "maps" / "box.txt")
    text = ('map = { file = "maps/box.txt", bounds = [-1.0, -1.0, 11.0, 7.0] }\n'
            'robots = [{ type = "Pioneer2DX", x = 2.0, y = 2.0 }]\n')
    s = load_scenario_toml(write(tmp_path, text))
    assert s.map.bounds == (-1.0, -1.0, 11.0, 7.0) and len(s.map.segments) == 4
    short = write(tmp_path, 'map = "maps/box.txt"\nrobots = [{ type = "Pioneer2DX", x = 2.0, '
                            'y = 2.0 }]\n', "short.toml")
    assert load_scenario_toml(short).map == Map.box(10.0, 6.0)


ROBOT = '[[robots]]\ntype = "Pioneer2DX"\nx = 2.0\ny = 2.0\n'


@pytest.mark.parametrize(("text", "expected"), [
    # unknown keys
    (ROOM + ROBOT + "colour = 3\n", r"line 6: robots\[0\]\.colour: unknown key"),
    (ROOM + "speed = 2\n" + ROBOT, r"line 2: speed: unknown key \(expected one of name"),
    (ROOM + ROBOT + "[settings]\ndtt = 0.1\n", r"line 7: settings\.dtt: unknown key"),
    (ROOM + ROBOT + "[types.Tiny]\nbase = \"Pioneer2DX\"\nwidht = 0.1\n",
     r"line 6: types\.Tiny: unknown key 'widht'"),
    # wrong types
    (ROOM + ROBOT.replace("x = 2.0", 'x = "two"'), r"line 4: robots\[0\]\.x: expected a number, "
                                                   r"got 'two'"),
    (ROOM + ROBOT + "goal = [1.0]\n", r"line 6: robots\[0\]\.goal: expected \[x, y\]"),
    (ROOM + ROBOT + "[settings]\ndt = \"fast\"\n", r"line 7: settings\.dt: expected a number"),
    (ROOM + ROBOT + "[settings]\ndt = -0.1\n", r"line 7: settings\.dt: expected a positive"),
    (ROOM + "robots = 3\n", r"line 2: robots: expected a non-empty list"),
    (ROOM + '[[robots]]\ngenerator = "line"\ntype = "Pioneer2DX"\ncount = 2.5\nstart = [1.0, '
            '1.0]\nstep = [1.0, 0.0]\n', r"line 5: robots\[0\]\.count: expected a whole number"),
    # missing fields
    (ROOM + '[[robots]]\ntype = "Pioneer2DX"\nx = 2.0\n', r"line 2: robots\[0\]: missing key "
                                                          r"'y'"),
    ('[[robots]]\ntype = "Pioneer2DX"\nx = 2.0\ny = 1.0\n', r"missing key 'map'"),
    (ROOM, r"missing key 'robots'"),
    # names that do not exist
    (ROOM + ROBOT.replace("Pioneer2DX", "Pioneer9"), r"line 3: robots\[0\]\.type: unknown robot "
                                                     r"type 'Pioneer9'"),
    (ROOM + '[[robots]]\ngenerator = "spiral"\n', r"line 3: robots\[0\]\.generator: unknown "
                                                  r"generator 'spiral'"),
    ('map = "stage:moon"\n' + ROBOT, r"line 1: map\.builtin: unknown built-in map 'stage:moon'"),
    ('map = "nowhere.txt"\n' + ROBOT, r"line 1: map\.file: .*nowhere\.txt: map file not found"),
    # the start state
    (ROOM + ROBOT + ROBOT.replace("x = 2.0", "x = 2.2"),
     r"robots\[0\] \(line 2\) at \(2, 2\) and robots\[1\] \(line 6\) at \(2.2, 2\) overlap"),
    (ROOM + ROBOT.replace("y = 2.0", "y = 0.1"), r"robots\[0\] \(line 2\): robot at \(2, 0.1\) "
                                                 r"touches wall 0"),
    (ROOM + ROBOT + "goal = [30.0, 1.0]\n", r"robots\[0\] \(line 2\): goal \(30, 1\) is outside "
                                            r"the map bounds \(-1, -1, 11, 7\)"),
    (ROOM + ROBOT.replace("x = 2.0", "x = 12.0"), r"start \(12, 2\) is outside the map bounds"),
    (ROOM + '[[robots]]\ngenerator = "random"\ntype = "Pioneer2DX"\ncount = 500\nmax_tries = 64\n',
     r"line 2: robots\[0\]: cannot place robot \d+ of 500"),
    # syntax
    (ROOM + "[[robots]\n", r"not valid TOML: .*line 2"),
])
def test_schema_errors_are_one_line_naming_file_key_and_line(tmp_path: Path, text: str,
                                                              expected: str) -> None:
    file_error(load_scenario_toml, tmp_path / "scenario.toml", text, match=expected,
               error=ScenarioError)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match="scenario file not found"):
        load_scenario_toml(tmp_path / "none.toml")


def test_validate_python_scenarios() -> None:
    rows = [[0.0, 0.0, 0.0, 0.0], [0.3, 0.0, 1.0, 0.0]]
    s = Scenario.from_matrix(rows, Map.empty((-5, -5, 5, 5)), PIONEER_2DX, name="pair")
    with pytest.raises(ScenarioError, match=r"in python: robot 0 at .* and robot 1 .* overlap"):
        validate_scenario(s, "in python")
    apart = Scenario.from_matrix([[0.0, 0.0, 0.0, 0.0], [0.5, 0.0, 1.0, 0.0]],
                                 Map.empty((-5, -5, 5, 5)), PIONEER_2DX)
    validate_scenario(apart)


def random_bodies(rng: np.random.Generator, n: int, spread: float) -> Bodies:
    return Bodies(rng.uniform(-spread, spread, (n, 2)), rng.uniform(-np.pi, np.pi, n),
                  rng.uniform(0.05, 0.5, n), rng.uniform(0.05, 0.5, n))


def rectangle(bodies: Bodies, i: int) -> shapely.Polygon:
    c, s = np.cos(bodies.headings[i]), np.sin(bodies.headings[i])
    hl, hw = bodies.half_length[i], bodies.half_width[i]
    local = np.array([[hl, hw], [-hl, hw], [-hl, -hw], [hl, -hw]])
    return shapely.Polygon(bodies.centers[i] + local @ np.array([[c, s], [-s, c]]))


def test_overlap_checks_agree_with_shapely_and_the_engine() -> None:
    rng = np.random.default_rng(7)
    for _ in range(5):
        bodies = random_bodies(rng, 60, 4.0)
        segments = rng.uniform(-4.5, 4.5, (40, 4))
        shapes = [rectangle(bodies, i) for i in range(60)]
        walls = [shapely.LineString(s.reshape(2, 2)) for s in segments]
        robot, seg = touching_walls(bodies, segments)
        assert set(zip(robot.tolist(), seg.tolist(), strict=True)) == {
            (i, k) for i in range(60) for k in range(40) if shapes[i].intersects(walls[k])}
        first, second = overlapping_robots(bodies)
        assert set(zip(first.tolist(), second.tolist(), strict=True)) == {
            (i, j) for i in range(60) for j in range(i + 1, 60)
            if shapes[i].intersects(shapes[j])}
        # the engine's exact check finds the same robots in contact
        engine = EngineBodies(bodies.centers, bodies.headings, bodies.half_length,
                              bodies.half_width)
        solid = np.ones(60, dtype=bool)
        bounds = (-6.0, -6.0, 6.0, 6.0)
        with_whom, _ = find_collisions(engine, solid, solid, build_segment_grid(segments, bounds),
                                       build_robot_index(*engine, solid))
        in_contact = set(robot.tolist()) | set(first.tolist()) | set(second.tolist())
        assert set(np.flatnonzero(with_whom != -2).tolist()) == in_contact


def test_random_placement_keeps_clear_of_walls_and_others() -> None:
    room = Map.box(6.0, 4.0)
    poses = random_placement(12, PIONEER_2DX, room, np.random.default_rng(0), min_spacing=0.8,
                             clearance=0.2)
    bodies = Bodies(poses[:, :2], poses[:, 2], np.full(12, PIONEER_2DX.length / 2),
                    np.full(12, PIONEER_2DX.width / 2))
    assert touching_walls(bodies, room.segments, grow=0.2)[0].size == 0
    distance = np.hypot(*(poses[:, None, :2] - poses[None, :, :2]).transpose(2, 0, 1))
    assert distance[np.triu_indices(12, 1)].min() >= 0.8
    with pytest.raises(ScenarioError, match="cannot place robot"):
        random_placement(200, PIONEER_2DX, room, np.random.default_rng(0), max_tries=64)
