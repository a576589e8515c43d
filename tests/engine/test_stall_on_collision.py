"""``on_collision = "stall"``: a robot that bumps is put back, stays active and is flagged
stalled for the step, as Stage's robots are (issue 49, item 5).

Independent truths: shapely's polygons of the robots' rectangles and of the walls (no
two robots overlap, none touches a wall, at the end of any step; the first stall comes
at the first step where the same robot driven without the wall would touch it), and
hand-built scenes whose geometry says who must be put back.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, Polygon

from mimics.catalog import load_scenario
from mimics.engine.simulation import Simulation
from mimics.engine.state import Status
from mimics.world.errors import MimicsError, ScenarioError
from mimics.world.maps import Map
from mimics.world.robot_types import RobotType
from mimics.world.scenario import Scenario, Settings
from mimics.world.scenario_files import load_scenario_toml

BLIND = RobotType("blind", width=0.5, length=0.7, kv=1.0, kw=1.0, tau_v=0.5, tau_w=0.2)
HALF_LENGTH, HALF_WIDTH = 0.35, 0.25


def scene(rows: list[list[float]], walls: list[list[float]] = (),
          bounds: tuple[float, ...] = (-10, -10, 10, 10), **settings: object) -> Scenario:
    """Robots ``[x, y, yaw, v]`` (no goals) of type BLIND among ``walls``."""
    world = Map(np.array(walls, dtype=float).reshape(-1, 4), bounds)
    return Scenario.from_matrix(rows, world, BLIND, settings=Settings(noise="off", **settings))


def rectangle(pose: np.ndarray) -> Polygon:
    """A robot's body at ``pose``, by hand: its four corners."""
    x, y, theta = (float(v) for v in pose)
    c, s = math.cos(theta), math.sin(theta)
    return Polygon([(x + c * a - s * b, y + s * a + c * b)
                    for a, b in ((HALF_LENGTH, HALF_WIDTH), (-HALF_LENGTH, HALF_WIDTH),
                                 (-HALF_LENGTH, -HALF_WIDTH), (HALF_LENGTH, -HALF_WIDTH))])


def assert_apart(sim: Simulation, walls: list[LineString]) -> None:
    """No two solid robots overlap or touch, and no robot touches a wall (shapely)."""
    state = sim.state
    bodies = [rectangle(state.pose[i]) for i in range(state.n)]
    for i, body in enumerate(bodies):
        assert all(body.distance(wall) > 0 for wall in walls), (state.step, i)
        for j in range(i + 1, state.n):
            assert body.distance(bodies[j]) > 0, (state.step, i, j)


def scripted(commands):
    """An algorithm returning ``commands(time)`` = ``(speed, heading)`` for every robot."""
    def step(robot):
        robot.memory.setdefault("stalled", []).append(robot.stalled)
        return commands(robot.time)
    return step


# -- one robot and a wall ---------------------------------------------------

WALL_X = 3.0
WALL = [[WALL_X, -5.0, WALL_X, 5.0]]


def wall_then_away(t: float) -> tuple[float, float]:
    """Forward at the wall for 6 s, back off for 2 s, then turn away and drive on."""
    if t < 6.0 - 1e-9:
        return 0.8, 0.0
    if t < 8.0 - 1e-9:
        return -0.5, 0.0
    return 0.5, math.pi / 2


def test_a_robot_driven_at_a_wall_stalls_at_its_last_free_pose_stays_active_and_leaves():
    stalled_run = Simulation(scene([[0.0, 0.0, 0.0, 0.0]], WALL, on_collision="stall"),
                             scripted(wall_then_away), seed=1, time_limit=12.0)
    free_run = Simulation(scene([[0.0, 0.0, 0.0, 0.0]]), scripted(wall_then_away), seed=1,
                          time_limit=12.0)
    wall = LineString([(WALL_X, -5.0), (WALL_X, 5.0)])
    poses, flags = [stalled_run.state.pose[0].copy()], [False]
    free_poses = [free_run.state.pose[0].copy()]
    stalled_run.start()
    free_run.start()
    first_touch = None  # the first step at which the robot driven without the wall touches it
    while stalled_run.step():
        free_run.step()
        free_poses.append(free_run.state.pose[0].copy())
        assert_apart(stalled_run, [wall])
        assert stalled_run.state.status[0] == Status.ACTIVE
        poses.append(stalled_run.state.pose[0].copy())
        flags.append(bool(stalled_run.state.stalled[0]))
        if first_touch is None and rectangle(free_run.state.pose[0]).distance(wall) <= 1e-9:
            first_touch = stalled_run.state.step
    poses, flags = np.array(poses), np.array(flags)
    first_stall = int(np.argmax(flags))
    assert first_touch is not None and first_stall == first_touch
    # up to it, the same run as without the wall, bit for bit
    np.testing.assert_array_equal(poses[:first_stall], free_poses[:first_stall])
    for k in np.flatnonzero(flags):
        np.testing.assert_array_equal(poses[k], poses[k - 1])  # put back: it did not move
    # pressed at the wall, it stands within one step's move of it and then backs off
    pressed = round(6.0 / 0.1)
    assert flags[pressed] and 0 < WALL_X - HALF_LENGTH - poses[pressed, 0] < 0.08
    assert not flags[pressed + 2:].any()
    assert poses[-1, 1] > 1.0 and poses[-1, 0] < poses[pressed, 0]  # it drove away
    result = stalled_run.result()
    assert result.final_status[0] == Status.ACTIVE and result.status == "time_limit"
    events = [e for e in result.events if e.kind == "collision"]
    rises = int(np.count_nonzero(flags[1:] & ~flags[:-1]))
    assert len(events) == rises >= 1  # one per stall that began, none after backing off
    assert all(e.other == -1 and e.time <= 6.0 for e in events)
    assert result.summary()["collisions"] == result.summary()["wall_collisions"] == 1
    # the algorithm read the same flags as robot.stalled, one step later (at its sensing)
    seen = stalled_run.state.memory[0]["stalled"]
    assert seen == flags[:len(seen)].tolist()


def test_a_stalled_robot_has_not_moved_its_odometer_nor_its_path_and_stands_still():
    sim = Simulation(scene([[0.0, 0.0, 0.0, 0.0]], WALL, on_collision="stall"),
                     scripted(lambda t: (0.8, 0.0)), seed=1, time_limit=5.0)
    sim.start()
    while sim.step():
        if sim.state.stalled[0]:
            break
    state = sim.state
    before = state.path_length[0]
    np.testing.assert_array_equal(state.velocity[0], [0.0, 0.0])
    np.testing.assert_array_equal(state.odometry[0], state.pose[0])  # noise off: exact
    assert state.path_length[0] == pytest.approx(state.pose[0, 0])  # straight from x = 0
    sim.step()
    assert state.path_length[0] >= before


# -- two robots --------------------------------------------------------------

def test_two_robots_driven_head_on_both_stall_and_stay_apart():
    rows = [[-1.0, 0.0, 0.0, 0.0], [1.0, 0.0, math.pi, 0.0]]
    headings = (0.0, math.pi)

    def step(robot):
        return 0.6, headings[robot.id]

    sim = Simulation(scene(rows, on_collision="stall"), step, seed=2, time_limit=5.0)
    sim.start()
    stalled = np.zeros(2, dtype=bool)
    while sim.step():
        assert_apart(sim, [])
        stalled |= sim.state.stalled
    assert stalled.all()
    result = sim.result()
    assert (result.final_status == Status.ACTIVE).all()
    gap = sim.state.pose[1, 0] - sim.state.pose[0, 0] - 2 * HALF_LENGTH
    assert 0 < gap < 0.1  # they came close, and stopped short of each other
    firsts = {e.robot: e.other for e in result.events if e.kind == "collision"}
    assert firsts == {0: 1, 1: 0}
    assert result.summary()["robot_collisions"] == result.collisions == 2


def first_step_distance() -> float:
    """How far a robot of the chain moves in its first step (x, heading 0, no walls)."""
    sim = Simulation(scene([[0.0, 0.0, 0.0, 1.0]]), lambda robot: (1.0, 0.0), time_limit=0.1)
    sim.run()
    return float(sim.state.pose[0, 0])


def chain(on_collision: str) -> Simulation:
    """B's first move touches the wall; A, behind it, moves into B's old place but not
    into B's new one: only B's being put back makes A touch it."""
    d = first_step_distance()
    b_x = 0.0
    wall_x = b_x + HALF_LENGTH + d / 2
    a_x = b_x - 2 * HALF_LENGTH - d / 2
    rows = [[a_x, 0.0, 0.0, 1.0], [b_x, 0.0, 0.0, 1.0]]
    return Simulation(scene(rows, [[wall_x, -3.0, wall_x, 3.0]], on_collision=on_collision),
                      lambda robot: (1.0, 0.0), time_limit=0.1)


def test_a_chain_a_robot_moving_into_the_place_of_one_put_back_is_put_back_too():
    start = chain("stall").state.pose.copy()
    sim = chain("stall")
    wall = LineString([(float(sim.scenario.map.segments[0, 0]), -3.0),
                       (float(sim.scenario.map.segments[0, 0]), 3.0)])
    result = sim.run()
    assert_apart(sim, [wall])
    np.testing.assert_array_equal(sim.state.pose, start)  # both where they were
    assert sim.state.stalled.tolist() == [True, True]
    assert (result.final_status == Status.ACTIVE).all()
    firsts = {e.robot: e.other for e in result.events if e.kind == "collision"}
    assert firsts == {0: 1, 1: -1}
    # the same scene deactivating: only B touches anything (A never reaches B's new place)
    deactivated = chain("deactivate").run()
    assert deactivated.final_status.tolist() == [Status.ACTIVE, Status.COLLIDED]


SIDE = 4.0
ROOM = (0.0, 0.0, SIDE, SIDE)
ROOM_WALLS = [[0, 0, SIDE, 0], [SIDE, 0, SIDE, SIDE], [SIDE, SIDE, 0, SIDE], [0, SIDE, 0, 0]]

robot_rows = st.lists(st.tuples(st.floats(0.45, SIDE - 0.45), st.floats(0.45, SIDE - 0.45),
                                st.floats(-math.pi, math.pi), st.floats(-1.0, 1.0)),
                      min_size=2, max_size=5)
#: (speed, heading off the direction of the room's centre): most drive into each other
commands = st.lists(st.tuples(st.floats(-1.0, 1.0), st.floats(-math.pi, math.pi)),
                    min_size=4, max_size=4)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rows=robot_rows, plan=commands, seed=st.integers(0, 2**16))
def test_after_every_step_no_two_robots_overlap_and_none_touches_a_wall(rows, plan, seed):
    bodies = [rectangle(np.array(row[:3])) for row in rows]
    walls = [LineString([(a, b), (c, d)]) for a, b, c, d in ROOM_WALLS]
    assume(all(body.distance(wall) > 0.01 for body in bodies for wall in walls))
    assume(all(bodies[i].distance(bodies[j]) > 0.01
               for i in range(len(bodies)) for j in range(i + 1, len(bodies))))

    def step(robot):  # each robot its own command, changing every second
        speed, offset = plan[(robot.id + int(robot.time + 1e-9)) % len(plan)]
        x, y = robot.true_pose[:2]
        return speed, math.atan2(SIDE / 2 - y, SIDE / 2 - x) + offset

    sim = Simulation(scene([list(r) for r in rows], ROOM_WALLS, bounds=ROOM,
                           on_collision="stall"), step, seed=seed, time_limit=4.0)
    sim.start()
    while sim.step():
        assert (sim.state.status == Status.ACTIVE).all()  # no goals: nobody leaves
        assert_apart(sim, walls)
        assert (sim.state.pose[:, :2] > 0).all() and (sim.state.pose[:, :2] < SIDE).all()


# -- the default, the setting and its errors --------------------------------

def test_the_default_is_the_deactivating_rule_unchanged():
    rows = [[-1.0, 0.0, 0.0, 0.0], [1.0, 0.0, math.pi, 0.0]]
    runs = [Simulation(scene(rows, **extra), lambda robot: (0.6, 0.0 if robot.id == 0
                                                             else math.pi), seed=3,
                       time_limit=4.0).run()
            for extra in ({}, {"on_collision": "deactivate"})]
    assert runs[0].trajectory_digest == runs[1].trajectory_digest
    assert runs[0].events_as_dicts() == runs[1].events_as_dicts()
    assert runs[0].final_status.tolist() == [Status.COLLIDED, Status.COLLIDED]
    assert runs[0].ever_stalled is None and runs[0].collisions == 2


def test_every_scenario_takes_on_collision_as_a_parameter():
    built = load_scenario("line", robots=2, on_collision="stall")
    assert built.settings.on_collision == "stall"
    assert built.parameters["on_collision"] == "stall"
    assert load_scenario("line", robots=2).settings.on_collision == "deactivate"


def test_a_scenario_file_sets_it_and_a_parameter_overrides_it(tmp_path):
    path = tmp_path / "room.toml"
    path.write_text('map = { segments = [[5, -2, 5, 2]], bounds = [-10, -10, 10, 10] }\n'
                    'robots = [{ type = "Pioneer2DX", x = 0.0, y = 0.0 }]\n'
                    '[settings]\non_collision = "stall"\n')
    assert load_scenario(str(path)).settings.on_collision == "stall"
    assert load_scenario_toml(str(path), on_collision="deactivate").settings.on_collision \
        == "deactivate"


@pytest.mark.parametrize("value", ["bounce", "", "Stall", 1, True])
def test_a_bad_value_is_one_error_naming_the_setting(value, tmp_path):
    with pytest.raises(ScenarioError, match=r"settings\.on_collision: expected one of "
                                            r"deactivate, stall"):
        Settings(on_collision=value)
    with pytest.raises(MimicsError, match="on_collision"):
        load_scenario("line", robots=2, on_collision=value)
    path = tmp_path / "bad.toml"
    literal = f'"{value}"' if isinstance(value, str) else str(value).lower()
    path.write_text('map = { segments = [], bounds = [-10, -10, 10, 10] }\n'
                    'robots = [{ type = "Pioneer2DX", x = 0.0, y = 0.0 }]\n'
                    f'[settings]\non_collision = {literal}\n')
    with pytest.raises(MimicsError, match=r"bad\.toml.*on_collision"):
        load_scenario(str(path))


def test_a_team_reads_every_robots_stall_flag():
    rows = [[-1.0, 0.0, 0.0, 0.0], [1.0, 0.0, math.pi, 0.0], [0.0, 3.0, 0.0, 0.0]]
    seen: list[list[bool]] = []

    def team_step(team):
        seen.append(team.stalled.tolist())
        speeds = np.where(team.ids < 2, 0.6, 0.0)
        return speeds, np.where(team.ids == 1, math.pi, 0.0)

    sim = Simulation(scene(rows, on_collision="stall"), team_step, seed=4, time_limit=4.0)
    flags = [sim.state.stalled.tolist()]
    sim.start()
    while sim.step():
        flags.append(sim.state.stalled.tolist())
    assert seen == flags[:len(seen)]
    assert any(row[0] and row[1] for row in seen) and not any(row[2] for row in seen)
