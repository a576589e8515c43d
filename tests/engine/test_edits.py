"""Edits of a running world (mimics.engine.edits) against hand-computed truth.

A three-beam ranger (right, ahead, left) without noise reads the distance
from the robot's centre to the first wall or robot along each beam: a robot
moved, a wall added or removed, a robot removed change those readings on the
next scan by amounts worked out by hand. Refused edits change nothing.
"""

from __future__ import annotations

import contextlib
import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.engine.simulation import Simulation
from mimics.engine.state import Status
from mimics.world.edits import EditError, edit_from_dict, walls_after
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX
from mimics.world.scenario import Scenario, Settings

EYE = replace(PIONEER_2DX, name="Eye", ranger=replace(PIONEER_2DX.ranger, beams=3, fov=math.pi,
                                                      range=8.0, sigma=0.0))
AHEAD, LEFT = 1, 2  # beams at 0 and +pi/2 from the heading
WALL_X = 5.0  # the one wall: x = 5, from y = -2 to 2


def still(robot):
    """Stands still, facing where it faces."""
    return 0.0, robot.heading


def driver(robot):
    """Drives ahead at full speed."""
    return robot.type.max_speed, robot.heading


def world(rows: list[list[float]], time_limit: float = 5.0) -> Scenario:
    walls = Map(np.array([[WALL_X, -2.0, WALL_X, 2.0]]), (-10.0, -10.0, 10.0, 10.0), name="box")
    return Scenario.from_matrix(rows, walls, EYE, Settings(noise="off", time_limit=time_limit))


def sim_of(rows: list[list[float]], algorithm=still, **kwargs) -> Simulation:
    sim = Simulation(world(rows, **kwargs), algorithm, seed=1)
    sim.start()
    return sim


def test_a_robot_moved_in_front_of_the_wall_reads_the_distance_to_it():
    sim = sim_of([[0.0, 5.0, 0.0, 0.0], [-5.0, -5.0, 0.0, 0.0]])
    assert sim.state.scan_hit[0, AHEAD] == -2  # at y = 5 the wall (up to y = 2) is not ahead
    sim.step()
    sim.state.velocity[0] = (0.3, 0.1)  # moving: the edit stops it
    applied = sim.edit({"kind": "move_robot", "robot": 0, "x": 2.0, "y": 0.5, "yaw": 0.0})
    assert (applied.step, applied.time) == (1, pytest.approx(0.1))
    assert sim.state.pose[0].tolist() == [2.0, 0.5, 0.0]
    assert sim.state.velocity[0].tolist() == [0.0, 0.0]
    assert sim.state.measured_pose[0].tolist() == [2.0, 0.5, 0.0]  # sensed again
    assert sim.state.scan[0, AHEAD] == pytest.approx(WALL_X - 2.0)
    assert sim.state.scan_hit[0, AHEAD] == -1
    # turned to face the wall from the side: the left beam meets it
    sim.edit({"kind": "move_robot", "robot": 0, "x": 1.0, "y": 0.0, "yaw": -math.pi / 2})
    assert sim.state.scan_hit[0, LEFT] == -1
    assert sim.state.scan[0, LEFT] == pytest.approx(WALL_X - 1.0)
    sim.step()  # the next step's scan, after the robots acted: the same (it stood still)
    assert sim.state.scan[0, LEFT] == pytest.approx(WALL_X - 1.0)


def test_an_added_wall_blocks_and_a_removed_wall_no_longer_blocks_the_ray():
    sim = sim_of([[1.0, 0.0, 0.0, 0.0]])
    assert sim.state.scan[0, AHEAD] == pytest.approx(WALL_X - 1.0)
    sim.edit({"kind": "add_wall", "segment": [3.0, -1.0, 3.0, 1.0]})
    assert sim.state.scan[0, AHEAD] == pytest.approx(2.0)
    assert sim.world_map.segments.shape == (2, 4)
    assert sim.scenario.map.segments.shape == (1, 4)  # the recipe keeps the first map
    sim.step()
    sim.edit({"kind": "remove_wall", "at": [3.2, 0.5]})  # nearest: the wall just added
    assert sim.state.scan[0, AHEAD] == pytest.approx(WALL_X - 1.0)
    applied = sim.edit({"kind": "remove_wall", "wall": 0})
    assert applied.edit.wall == 0 and sim.world_map.segments.shape == (0, 4)
    assert sim.state.scan_hit[0, AHEAD] == -2  # nothing left to hit


def test_a_rectangle_adds_four_walls_that_stop_a_robot_driving_into_them():
    sim = sim_of([[0.0, 0.0, 0.0, 0.0]], driver)
    sim.edit({"kind": "add_wall", "rectangle": [1.0, -1.0, 2.0, 1.0]})
    assert sim.state.scan[0, AHEAD] == pytest.approx(1.0)  # the rectangle's left side
    while sim.step():
        pass
    assert sim.state.status[0] == Status.COLLIDED
    assert sim.state.collided_with[0] == -1
    # it touched the side at x = 1: its front (half length 0.1625) got there
    assert sim.state.pose[0, 0] + EYE.length / 2 == pytest.approx(1.0, abs=0.05)


def test_a_removed_robot_no_longer_moves_is_seen_or_hit():
    sim = sim_of([[0.0, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0, 0.0], [0.0, 3.0, 0.0, 0.0]], driver,
                 time_limit=12.0)
    assert sim.state.scan_hit[0, AHEAD] == 1  # robot 1 is ahead of robot 0
    assert sim.state.scan[0, AHEAD] == pytest.approx(2.0 - EYE.length / 2)
    sim.edit({"kind": "remove_robot", "robot": 1})
    assert sim.state.status[1] == Status.REMOVED
    with pytest.raises(EditError, match=r"edit.robot: robot 1 was removed"):
        sim.edit({"kind": "set_goal", "robot": 1, "x": 0.0, "y": 0.0})
    assert sim.state.scan_hit[0, AHEAD] == -1  # the wall behind it now
    assert sim.state.scan[0, AHEAD] == pytest.approx(WALL_X)
    where = sim.state.pose[1].copy()
    while sim.step():  # robot 0 drives through where robot 1 stands, up to x = 3.4
        pass
    assert sim.state.pose[1].tolist() == where.tolist()
    assert sim.state.pose[0, 0] > 2.0 + EYE.length
    assert sim.state.status[0] == Status.ACTIVE and sim.status == "time_limit"
    assert sim.result().summary()["removed"] == 1


def test_removing_the_last_robot_ends_the_run():
    sim = sim_of([[0.0, 0.0, 0.0, 0.0]])
    sim.edit({"kind": "remove_robot", "robot": 0})
    assert sim.status == "completed" and not sim.step()
    with pytest.raises(EditError, match="the run has ended"):
        sim.edit({"kind": "add_wall", "segment": [0, 0, 1, 1]})


def test_a_new_goal_is_driven_to():
    sim = sim_of([[0.0, 0.0, 0.0, 0.0]], driver)
    sim.edit({"kind": "set_goal", "robot": 0, "x": 1.0, "y": 0.0})
    assert sim.state.goal[0].tolist() == [1.0, 0.0]
    while sim.step():
        pass
    assert sim.state.status[0] == Status.REACHED_GOAL
    assert abs(sim.state.pose[0, 0] - 1.0) <= sim.scenario.settings.goal_tolerance


@pytest.mark.parametrize(("edit", "message"), [
    ({"kind": "move_robot", "robot": 0, "x": 5.0, "y": 0.0},
     "edit: robot 0 at (5, 0) would touch wall 0 (5, -2)-(5, 2)"),
    # the half length 0.1625 reaches the wall from 0.1 m away, not from 0.2
    ({"kind": "move_robot", "robot": 0, "x": WALL_X - 0.1, "y": 0.0, "yaw": 0.0},
     "would touch wall 0"),
    ({"kind": "move_robot", "robot": 0, "x": 2.1, "y": 0.1},
     "edit: robot 0 at (2.1, 0.1) would overlap robot 1"),
    ({"kind": "move_robot", "robot": 0, "x": 12.0, "y": 0.0},
     "edit: robot 0 at (12, 0) is outside the map bounds (-10, -10, 10, 10)"),
    ({"kind": "move_robot", "robot": 5, "x": 1.0, "y": 0.0},
     "edit.robot: no robot 5 (the run has 2: 0 to 1)"),
    ({"kind": "set_goal", "robot": 0, "x": 5.05, "y": 1.0},
     "edit: robot 0's goal (5.05, 1) is in wall 0 (5, -2)-(5, 2)"),
    ({"kind": "set_goal", "robot": 0, "x": 0.0, "y": -11.0},
     "edit: robot 0's goal (0, -11) is outside the map bounds"),
    ({"kind": "add_wall", "segment": [2.0, -1.0, 2.0, 1.0]},
     "edit: the wall would touch robot 1 at (2, 0)"),
    ({"kind": "add_wall", "rectangle": [-0.5, -0.5, 0.5, 0.5]},  # around robot 0, apart
     "edit: the rectangle would enclose robot 0 at (0, 0)"),
    ({"kind": "remove_wall", "wall": 1}, "edit.wall: no wall 1 (the map has 1: 0 to 0)"),
    ({"kind": "remove_wall", "at": [3.9, 0.0]}, "edit.at: no wall within 1 m of (3.9, 0)"),
])
def test_refused_edits_change_nothing(edit, message):
    sim = sim_of([[0.0, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0, 0.0]])
    pose, goal = sim.state.pose.copy(), sim.state.goal.copy()
    with pytest.raises(EditError) as error:
        sim.edit(edit)
    assert message in str(error.value)
    assert np.array_equal(sim.state.pose, pose)
    assert np.array_equal(sim.state.goal, goal, equal_nan=True)
    assert sim.world_map.segments.tolist() == [[WALL_X, -2.0, WALL_X, 2.0]]
    assert sim.scenario.edits == () and not [e for e in sim.events if e.kind == "edit"]


def test_a_rectangle_around_a_robot_is_refused_but_one_around_a_removed_robot_is_not():
    sim = sim_of([[0.0, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0, 0.0]])
    box = {"kind": "add_wall", "rectangle": [1.5, -0.5, 2.5, 0.5]}
    with pytest.raises(EditError, match="robot 1"):
        sim.edit(box)
    sim.edit({"kind": "remove_robot", "robot": 1})
    sim.edit(box)
    assert sim.world_map.segments.shape == (5, 4)


def test_scheduled_edits_apply_at_their_step_as_live_ones_do():
    rows = [[0.0, 0.0, 0.0, 0.0], [0.0, 3.0, 0.0, 0.0]]
    live = sim_of(rows, driver)
    for _ in range(4):
        live.step()
    live.edit({"kind": "add_wall", "segment": [1.5, -1.0, 1.5, 1.0]})
    live.edit({"kind": "move_robot", "robot": 1, "x": -3.0, "y": 3.0, "yaw": 1.0})
    for _ in range(3):
        live.step()
    live.edit({"kind": "remove_robot", "robot": 1})
    while live.step():
        pass
    timeline = live.scenario.edits
    assert [(e.step, e.kind) for e in timeline] == [(4, "add_wall"), (4, "move_robot"),
                                                   (7, "remove_robot")]
    walls = walls_after(live.scenario.map.segments, timeline)  # what a replay draws
    assert walls.tolist() == live.world_map.segments.tolist()
    assert walls_after(live.scenario.map.segments, timeline, step=3).tolist() == [
        [WALL_X, -2.0, WALL_X, 2.0]]
    replayed = Simulation(replace(world(rows), edits=timeline), driver, seed=1).run()
    assert replayed.trajectory_digest == live.run_digest()
    assert replayed.status == live.status and replayed.steps == live.state.step
    kinds = [(e.robot, e.kind) for e in replayed.events if e.kind == "edit"]
    assert kinds == [(-1, "edit"), (1, "edit"), (1, "edit")]


def test_a_scheduled_edit_refused_at_its_step_is_an_event_and_the_run_goes_on():
    rows = [[0.0, 0.0, 0.0, 0.0]]
    scenario = replace(world(rows), edits=(
        edit_from_dict({"step": 2, "kind": "add_wall", "segment": [0.0, -1.0, 0.0, 1.0]}),))
    result = Simulation(scenario, still, seed=1).run()
    refused = [e for e in result.events if e.kind == "edit_refused"]
    assert len(refused) == 1 and "would touch robot 0" in refused[0].detail
    assert result.status == "time_limit"



coordinate = st.floats(-9.0, 9.0, allow_nan=False).map(lambda v: round(v, 3))


@st.composite
def live_edits(draw: st.DrawFn) -> dict:
    kind = draw(st.sampled_from(["move_robot", "add_wall", "remove_wall", "set_goal",
                                 "remove_robot"]))
    robot = draw(st.integers(0, 3))  # robot 3 does not exist: refused
    if kind == "move_robot":
        return {"kind": kind, "robot": robot, "x": draw(coordinate), "y": draw(coordinate),
                "yaw": draw(st.floats(-3.0, 3.0))}
    if kind == "set_goal":
        return {"kind": kind, "robot": robot, "x": draw(coordinate), "y": draw(coordinate)}
    if kind == "remove_robot":
        return {"kind": kind, "robot": robot}
    if kind == "remove_wall":
        return {"kind": kind, "wall": draw(st.integers(0, 3))}
    x, y = draw(coordinate), draw(coordinate)
    return {"kind": kind, "segment": [x, y, x + draw(st.floats(0.1, 3.0)), y]}


@settings(max_examples=15, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 25), live_edits()), max_size=6))
def test_any_live_edits_rerun_from_their_timeline_to_the_same_digest(plan):
    """Whatever is edited when (refusals included), the recorded timeline run again
    gives the live run's digest, events and final walls."""
    rows = [[-3.0, 0.0, 0.0, 0.0, 6.0, 1.0], [-3.0, 2.0, 0.0, 0.0, 6.0, -1.0],
            [0.0, -4.0, 1.5, 0.0, 0.0, 4.0]]
    live = Simulation(world(rows, time_limit=3.0), driver, seed=2)
    live.start()
    for at_step, edit in sorted(plan, key=lambda item: item[0]):
        while live.state.step < at_step and live.step():
            pass
        if live.status != "running":
            break
        with contextlib.suppress(EditError):  # refused: nothing changed, nothing recorded
            live.edit(edit)
    while live.step():
        pass
    again = Simulation(replace(world(rows, time_limit=3.0), edits=live.scenario.edits), driver,
                       seed=2)
    result = again.run()
    assert result.trajectory_digest == live.run_digest()
    assert again.world_map.segments.tolist() == live.world_map.segments.tolist()
    assert [(e.time, e.robot, e.kind, e.detail) for e in result.events] == \
        [(e.time, e.robot, e.kind, e.detail) for e in live.events]
