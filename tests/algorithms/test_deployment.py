"""Deployment: the per-robot and team forms agree, and the Cave runs without collisions."""

import numpy as np
import pytest

from mimics.algorithms import deployment, deployment_team, go_to_goal
from mimics.engine.simulation import Simulation
from mimics.scenarios import cave, obstacle_room
from tests.stage import stage_file


@pytest.fixture  # each test: the Stage data is given back to one test at a time
def stage() -> None:
    stage_file("cave_filled.png")


def test_both_forms_give_identical_trajectories(stage: None) -> None:
    scenario = cave.scenario(robots=20)
    poses = []
    for algorithm in (deployment, deployment_team):
        sim = Simulation(scenario, algorithm, seed=3, time_limit=10.0)
        result = sim.run()
        assert result.summary()["collisions"] == 0
        poses.append(sim.state.pose.copy())
    assert np.array_equal(poses[0], poses[1])
    assert np.abs(poses[0][:, :2] - scenario.stages[:, :2]).max() > 0.5  # they did move


@pytest.mark.slow
def test_cave_deployment_has_no_collisions(stage: None) -> None:
    scenario = cave.scenario()
    sim = Simulation(scenario, deployment_team, seed=0, time_limit=60.0)
    summary = sim.run().summary()
    assert summary["status"] == "time_limit"
    assert summary["collisions"] == 0, sim.events[:3]
    moved = np.hypot(*(sim.state.pose[:, :2] - scenario.stages[:, :2]).T)
    assert (moved > 0.5).sum() >= 20  # spreading out, not standing still
    assert sim.state.pose[:, 1].min() < scenario.stages[:, 1].min() - 1.0  # heading south


def test_deployment_in_the_obstacle_room() -> None:
    sim = Simulation(obstacle_room.scenario(robots=8), deployment, seed=0, time_limit=30.0)
    assert sim.run().summary()["collisions"] == 0


def test_deployment_ignores_goals_and_go_to_goal_needs_them() -> None:
    from mimics.scenarios import corridor

    scenario = corridor.scenario(robots=2)
    summary = Simulation(scenario, go_to_goal, seed=0, time_limit=80.0).run().summary()
    assert summary["reached_goal"] + summary["collisions"] == 2  # head-on: straight to goals
    summary = Simulation(scenario, deployment, seed=0, time_limit=20.0).run().summary()
    assert summary["reached_goal"] == 0 and summary["collisions"] == 0
