"""What each built-in algorithm achieves on the two crossing scenarios, as its docstring says.

``circle_swap``: 8 Pioneer2DX on a 4 m circle, each bound for the opposite
point, so every straight path crosses the centre. ``corridor``: 10 robots,
5 each way, cross in a closed 16 x 3 m corridor. Seeds are fixed (the
scenarios have no noise, so every seed gives the same run).
"""

import numpy as np
import pytest

from mimics.algorithms import deployment, deployment_team, go_to_goal, go_to_goal_team
from mimics.engine.state import Status
from mimics.interfaces.api import simulate

SEED = 0


def statuses(run) -> np.ndarray:
    return np.asarray(run.final_status)


@pytest.mark.parametrize("algorithm", [go_to_goal, go_to_goal_team])
def test_go_to_goal_drives_straight_so_everyone_meets_head_on(algorithm):
    """It ignores obstacles: on both scenarios every robot collides with another robot."""
    for name, robots in (("circle_swap", 8), ("corridor", 10)):
        run = simulate(name, algorithm, seed=SEED)
        assert run.robots == robots
        assert (statuses(run) == Status.COLLIDED).all(), name
        assert (np.asarray(run.collided_with) >= 0).all(), f"{name}: a wall was hit"
        # the circle's robots meet near its centre, at most one robot length off
        if name == "circle_swap":
            times = [e.time for e in run.events if e.kind == "collision"]
            assert 10.0 < min(times) < 20.0  # 4 m at 0.3 m/s, minus the robots' size


def test_go_to_goal_team_is_the_per_robot_logic_at_once():
    for name in ("circle_swap", "corridor"):
        one = simulate(name, go_to_goal, seed=SEED)
        team = simulate(name, go_to_goal_team, seed=SEED)
        assert statuses(one).tolist() == statuses(team).tolist()
        assert np.allclose(one.path_length, team.path_length, atol=1e-9)


def test_wall_aware_stops_short_on_the_circle_instead_of_colliding():
    run = simulate("circle_swap", "wall_aware", seed=SEED)
    assert run.collisions == 0
    assert (statuses(run) == Status.DEADLOCK).all()
    assert run.reached_goal == 0


def test_wall_aware_lets_some_robots_through_the_corridor_and_never_hits_a_wall():
    # 66 s: the first robots through arrive after about a minute
    run = simulate("corridor", "wall_aware", seed=SEED, time=66.0)
    assert run.reached_goal >= 1
    assert run.collisions < run.robots // 2  # go_to_goal: all of them
    collided = statuses(run) == Status.COLLIDED
    assert (np.asarray(run.collided_with)[collided] >= 0).all()  # robots only, no walls


@pytest.mark.parametrize("name, algorithm", [("circle_swap", deployment),
                                             ("corridor", deployment_team)])
def test_deployment_ignores_goals_and_settles_without_collisions(name, algorithm):
    """It spreads out by the laser: nobody collides, nobody heads for a goal, all come to rest."""
    run = simulate(name, algorithm, seed=SEED)
    assert run.collisions == 0, name
    assert run.reached_goal == 0, name
    # at rest (a robot with a goal that stays put for the deadlock window counts as one)
    assert (statuses(run) == Status.DEADLOCK).all(), name
