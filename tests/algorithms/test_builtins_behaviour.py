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
            times = run.events.loc[run.events["kind"] == "collision", "time"].tolist()
            assert 10.0 < min(times) < 20.0  # 4 m at 0.3 m/s, minus the robots' size


def test_wall_aware_turns_the_circle_into_a_roundabout():
    """Keeping right, all 8 robots get round one another to the opposite point."""
    run = simulate("circle_swap", "wall_aware", seed=SEED)
    assert run.collisions == 0
    assert run.reached_goal == 8
    assert run.sim_time < 60.0  # the scenario's limit: nobody was left going round


def test_wall_aware_drives_a_lone_robot_that_sees_nothing_to_its_goal():
    """One robot on the open line: no beam hits anything, every path is clear
    (it raised on the empty set of hits before session 8)."""
    run = simulate("line", "wall_aware", robots=1, seed=SEED)
    assert run.status == "completed"
    assert run.reached_goal == 1


def test_wall_aware_crosses_the_corridor_without_collisions():
    """Two rows meet in a 3 m corridor: they squeeze past on the right, touching nothing.

    The first robots through arrive after about a minute (all but one by 300 s,
    measured once; 80 s here keeps the test short).
    """
    run = simulate("corridor", "wall_aware", seed=SEED, time=80.0)
    assert run.collisions == 0
    assert run.reached_goal >= 2
    assert int(np.sum(run.ever_deadlocked)) == 0


@pytest.mark.parametrize("name, algorithm", [("circle_swap", deployment),
                                             ("corridor", deployment_team)])
def test_deployment_ignores_goals_and_settles_without_collisions(name, algorithm):
    """It spreads out by the laser: nobody collides, nobody heads for a goal, all come to rest."""
    run = simulate(name, algorithm, seed=SEED)
    assert run.collisions == 0, name
    assert run.reached_goal == 0, name
    # at rest (a robot with a goal that stays put for the deadlock window counts as one)
    assert (statuses(run) == Status.DEADLOCK).all(), name
