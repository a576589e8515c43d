"""Every example in ``examples/`` runs and does what its README says.

Each claim is checked against independent truth: the recorded true poses, and
the map's geometry through shapely (distances to walls, free cells).
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import pandas as pd
import pytest
import shapely

import mimics
from mimics.engine.state import Status

ROOT = Path(__file__).resolve().parents[2]


def _load_gallery() -> ModuleType:
    spec = importlib.util.spec_from_file_location("mimics_examples_gallery",
                                                  ROOT / "examples" / "gallery.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


gallery = _load_gallery()


def _run(name: str, tmp_path: Path, time: float | None = None, **params):
    folder = tmp_path / name
    sim = gallery.simulate(name, folder, time=time, params=params)
    return sim, mimics.load_run(folder)


def _walls(run) -> shapely.MultiLineString:
    return shapely.MultiLineString([[(x1, y1), (x2, y2)]
                                    for x1, y1, x2, y2 in run.scenario.map.segments])


def _positions(trajectory: pd.DataFrame, step: int) -> np.ndarray:
    return trajectory[trajectory.step == step].sort_values("robot")[["x", "y"]].to_numpy()


def test_every_example_folder_has_its_parts_and_is_in_the_gallery() -> None:
    folders = sorted(p.parent.name for p in (ROOT / "examples").glob("*/algorithm.py"))
    assert folders == sorted(gallery.EXAMPLES)
    for name in folders:
        readme = (ROOT / "examples" / name / "README.md").read_text()
        assert "Sensors" in readme and f"examples/{name}/algorithm.py" in readme
        assert (ROOT / "examples" / name / "figure.png").stat().st_size > 10_000


def test_go_to_goal_brings_every_robot_of_the_line_to_its_goal(tmp_path: Path) -> None:
    sim, run = _run("go_to_goal", tmp_path)
    assert run.summary["reached_goal"] == 10 and run.summary["collisions"] == 0
    final = run.trajectory.groupby("robot").last()
    goals = sim.scenario.goals
    tolerance = sim.scenario.settings.goal_tolerance
    assert np.all(np.hypot(final.x - goals[:, 0], final.y - goals[:, 1]) <= tolerance)


def test_deployment_spreads_a_packed_group_without_collisions(tmp_path: Path) -> None:
    _, run = _run("deployment", tmp_path)
    trajectory = run.trajectory
    assert run.summary["collisions"] == 0

    def nearest_neighbour(points: np.ndarray) -> float:
        d = np.hypot(*(points[:, None, :] - points[None, :, :]).transpose(2, 0, 1))
        np.fill_diagonal(d, np.inf)
        return float(d.min(axis=1).mean())

    start = nearest_neighbour(_positions(trajectory, 0))
    end = nearest_neighbour(_positions(trajectory, trajectory.step.max()))
    assert start == pytest.approx(0.8)  # the grid's spacing
    assert end > 2 * start


def test_wall_following_keeps_a_wall_close_and_travels(tmp_path: Path) -> None:
    _, run = _run("wall_following", tmp_path, time=90.0)
    trajectory = run.trajectory
    assert run.summary["collisions"] == 0
    late = trajectory[trajectory.time >= 10.0]
    distance = shapely.distance(shapely.points(late.x, late.y), _walls(run))
    assert np.mean((distance >= 0.3) & (distance <= 1.2)) >= 0.9
    assert np.hypot(np.diff(trajectory.x), np.diff(trajectory.y)).sum() > 15.0


def test_frontier_exploration_maps_most_of_the_room_correctly(tmp_path: Path) -> None:
    sim, run = _run("frontier_exploration", tmp_path, time=90.0)
    assert run.summary["collisions"] == 0
    grid = sim.state.memory[0]["grid"]
    xmin, ymin = sim.scenario.map.bounds[:2]
    rows, cols = np.indices(grid.shape)
    centres = shapely.points(xmin + (cols + 0.5) * 0.1, ymin + (rows + 0.5) * 0.1)
    to_wall = shapely.distance(centres, _walls(run))
    boxes = shapely.union_all([shapely.Polygon(shapely.get_coordinates(
        shapely.MultiLineString([[(a, b), (c, d)] for a, b, c, d in segments])))
        for segments in np.split(sim.scenario.map.segments[4:], 4)])
    outside_boxes = ~shapely.contains(boxes, centres)
    clear = (to_wall > 0.3) & outside_boxes  # free, and not a cell a wall runs through
    believed_free, believed_occupied = grid < -0.2, grid > 0.2
    assert np.mean(believed_free[clear]) >= 0.6  # explored
    free = (to_wall > 0.1) & outside_boxes
    assert np.mean(free[believed_free]) >= 0.95  # what it calls free is free...
    assert np.mean(to_wall[believed_occupied] <= 0.2) >= 0.95  # ...and walls are walls


def test_reciprocal_avoidance_swaps_a_circle_without_a_collision(tmp_path: Path) -> None:
    _, run = _run("reciprocal_avoidance", tmp_path, robots=8, radius=4.0)
    assert run.summary["collisions"] == 0
    assert run.summary["reached_goal"] == 8


def test_rendezvous_gathers_the_robots_around_one_point(tmp_path: Path) -> None:
    sim, run = _run("rendezvous", tmp_path)
    trajectory = run.trajectory
    assert run.summary["collisions"] == 0

    def spread(points: np.ndarray) -> float:
        return float(np.hypot(*(points - points.mean(axis=0)).T).max())

    assert spread(_positions(trajectory, 0)) > 5.0
    assert spread(_positions(trajectory, trajectory.step.max())) < 2.5
    estimates = np.array([sim.state.memory[i]["estimate"] for i in range(8)])
    assert np.ptp(estimates, axis=0).max() < 0.05  # the consensus was reached


def test_leader_follower_keeps_the_formation_until_the_leader_arrives(tmp_path: Path) -> None:
    _, run = _run("leader_follower", tmp_path)
    trajectory = run.trajectory
    assert run.summary["collisions"] == 0
    assert run.robot(0).status.iloc[-1] == Status.REACHED_GOAL
    leader = trajectory[trajectory.robot == 0].set_index("step")
    leader = leader[leader.status == Status.ACTIVE]
    places = {1: (-1.2, 1.0), 2: (-1.2, -1.0), 3: (-2.4, 0.0)}  # (behind, left) of the leader
    cos, sin = np.cos(leader.theta), np.sin(leader.theta)
    settled = leader.time >= 20.0
    for robot, (behind, left) in places.items():
        follower = trajectory[trajectory.robot == robot].set_index("step").loc[leader.index]
        place_x = leader.x + cos * behind - sin * left
        place_y = leader.y + sin * behind + cos * left
        error = np.hypot(follower.x - place_x, follower.y - place_y)
        assert error[settled].max() < 0.3
