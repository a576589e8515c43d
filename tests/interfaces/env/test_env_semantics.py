"""What agents see, what their actions do, and what they are rewarded, against hand values."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import open_field

import mimics.env
from mimics.engine.simulation import Simulation
from mimics.engine.user_code import Team, TeamController
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario

HALF_WIDTH = 0.27 / 2  # Pioneer2DX


def test_first_observation_is_the_robots_pose_goal_and_scan(four_robots: Scenario) -> None:
    env = mimics.env.parallel_env(four_robots)
    observations, infos = env.reset(seed=0)
    assert env.agents == ["robot_0", "robot_1", "robot_2", "robot_3"]
    assert infos == {agent: {} for agent in env.agents}
    first = observations["robot_0"]
    np.testing.assert_array_equal(first["pose"], [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(first["velocity"], [0.0, 0.0])
    np.testing.assert_array_equal(first["goal"], [3.0, 0.0])  # 3 m straight ahead
    assert first["scan"].dtype == np.float32 and first["scan"].shape == (180,)
    # the leftmost beam (+90 degrees) ends on robot 1's near side, 2 m up, half a width less
    assert first["scan"][-1] == pytest.approx(2.0 - HALF_WIDTH, abs=1e-5)
    # the beams ahead see nothing within the 8 m range
    assert first["scan"][90] == pytest.approx(8.0)
    for agent, observation in observations.items():
        assert env.observation_space(agent).contains(observation)


def test_goal_is_given_in_the_robots_own_frame() -> None:
    # facing +y (yaw 90 degrees) with the goal 3 m along +x: the goal is 3 m to the right
    scenario = open_field([[0.0, 0.0, math.pi / 2, 0.0, 3.0, 0.0]])
    observations, _ = mimics.env.parallel_env(scenario, observation="flat").reset(seed=0)
    pose, goal = observations["robot_0"][:3], observations["robot_0"][5:7]
    np.testing.assert_allclose(pose, [0.0, 0.0, math.pi / 2], rtol=1e-6)
    np.testing.assert_allclose(goal, [0.0, -3.0], atol=1e-6)


@pytest.mark.parametrize(("heading", "action", "expected"), [
    ("relative", (0.2, 0.5), (0.2, math.pi / 2 + 0.5)),
    ("absolute", (0.2, 0.5), (0.2, 0.5)),
    ("relative", (5.0, -9.0), (0.3, math.pi / 2 - math.pi)),  # clipped to the box
    ("absolute", (-5.0, 9.0), (-0.3, math.pi)),
])
def test_actions_become_the_speed_and_heading_references(
        heading: str, action: tuple[float, float], expected: tuple[float, float]) -> None:
    scenario = open_field([[0.0, 0.0, math.pi / 2, 0.0, 3.0, 0.0]])
    env = mimics.env.parallel_env(scenario, heading=heading)
    env.reset(seed=0)
    env.step({"robot_0": np.array(action, dtype=np.float32)})
    np.testing.assert_allclose(env.sim.state.reference[0], expected, rtol=1e-6)


def test_the_env_runs_the_engine_as_an_algorithm_would(noisy_four_robots: Scenario) -> None:
    # constant references through the env and through a team algorithm: same bits
    speeds = np.array([0.25, 0.1, -0.2, 0.3])
    headings = np.array([0.1, -0.4, 0.0, 1.0])
    env = mimics.env.parallel_env(noisy_four_robots, heading="absolute", observation="flat")
    env.reset(seed=11)

    def team_step(team: Team) -> tuple[np.ndarray, np.ndarray]:
        return speeds[team.ids], headings[team.ids]

    sim = Simulation(noisy_four_robots, TeamController("constant", team_step=team_step), seed=11)
    sim.start()
    for _ in range(40):
        observations, *_ = env.step({a: (speeds[i], headings[i])
                                     for i, a in enumerate(env.possible_agents)})
        sim.step()
        for i, agent in enumerate(env.possible_agents):
            np.testing.assert_array_equal(observations[agent][:3],
                                          sim.state.measured_pose[i].astype(np.float32))
    np.testing.assert_array_equal(env.sim.state.pose, sim.state.pose)
    np.testing.assert_array_equal(env.sim.state.scan, sim.state.scan)


def test_default_reward_is_the_progress_toward_the_goal(four_robots: Scenario) -> None:
    env = mimics.env.parallel_env(four_robots, heading="absolute")
    env.reset(seed=0)
    for _ in range(5):
        before = env.sim.state.pose.copy()
        _, rewards, terminations, truncations, _ = env.step(
            {a: (0.3, 0.2) for a in env.agents})
        after = env.sim.state.pose
        for i, agent in enumerate(env.possible_agents):
            goal = (3.0, 2.0 * i)
            gained = (math.dist(before[i, :2], goal) - math.dist(after[i, :2], goal))
            assert rewards[agent] == pytest.approx(gained, abs=1e-12)
            assert gained != 0.0
        assert not any(terminations.values()) and not any(truncations.values())


def test_reaching_the_goal_pays_the_bonus_and_ends_the_agent() -> None:
    scenario = open_field([[2.75, 0.0, 0.0, 0.0, 3.0, 0.0], [0.0, 3.0, 0.0, 0.0, 5.0, 3.0]])
    env = mimics.env.parallel_env(scenario)
    env.reset(seed=0)
    for _ in range(10):
        before = env.sim.state.pose[0, :2].copy()
        _, rewards, terminations, _, infos = env.step({a: (0.3, 0.0) for a in env.agents})
        if terminations["robot_0"]:
            break
    gained = math.dist(before, (3.0, 0.0)) - math.dist(env.sim.state.pose[0, :2], (3.0, 0.0))
    assert infos["robot_0"] == {"status": "reached_goal"}
    assert rewards["robot_0"] == pytest.approx(gained + 10.0, abs=1e-12)
    assert env.agents == ["robot_1"]
    assert not terminations["robot_1"]


def test_collisions_and_escapes_are_penalised_and_end_the_agents() -> None:
    # robots 0 and 1 face each other 0.45 m apart; robot 2 drives off the map's edge, away from
    # its goal (a goal outside the map is refused when the scenario loads)
    scenario = open_field([[0.0, 0.0, 0.0, 0.0, 5.0, 0.0], [0.45, 0.0, math.pi, 0.0, -5.0, 0.0],
                           [9.95, 5.0, 0.0, 0.0, 5.0, 5.0]])
    env = mimics.env.parallel_env(scenario)
    env.reset(seed=0)
    ended: dict[str, tuple[float, dict]] = {}
    for _ in range(20):
        before = env.sim.state.pose[:, :2].copy()
        _, rewards, terminations, _, infos = env.step({a: (0.3, 0.0) for a in env.agents})
        for agent, done in terminations.items():
            if done:
                i = int(agent.split("_")[1])
                goal = env.scenario.goals[i]
                gained = math.dist(before[i], goal) - math.dist(env.sim.state.pose[i, :2], goal)
                ended[agent] = (rewards[agent] - gained, infos[agent])
        if not env.agents:
            break
    assert ended["robot_0"][0] == pytest.approx(-10.0)
    assert ended["robot_0"][1] == {"status": "collided"}
    assert ended["robot_1"][1] == {"status": "collided"}
    assert ended["robot_2"][0] == pytest.approx(-10.0)
    assert ended["robot_2"][1] == {"status": "escaped"}


def test_the_time_limit_truncates_every_live_agent(four_robots: Scenario) -> None:
    env = mimics.env.parallel_env(four_robots, time=1.0)
    env.reset(seed=0)
    for step in range(1, 11):
        _, _, terminations, truncations, _ = env.step({a: (0.0, 0.0) for a in env.agents})
        assert all(truncations.values()) == (step == 10)
        assert not any(terminations.values())
    assert env.agents == []
    with pytest.raises(MimicsError, match="call reset"):
        env.step({})


def test_user_reward_and_termination_functions(four_robots: Scenario) -> None:
    env = mimics.env.parallel_env(
        four_robots, heading="absolute",
        reward=lambda step: step.sim.state.pose[:, 0],  # x after the step
        terminate=lambda step: step.sim.state.pose[:, 0] > 0.05)
    env.reset(seed=0)
    speeds = {"robot_0": 0.3, "robot_1": 0.1, "robot_2": 0.0, "robot_3": -0.2}
    while "robot_0" in env.agents:
        _, rewards, terminations, _, _ = env.step({a: (speeds[a], 0.0) for a in env.agents})
        for agent, reward in rewards.items():
            assert reward == env.sim.state.pose[int(agent[-1]), 0]
    assert terminations["robot_0"]
    x = env.sim.state.pose[0, 0]
    assert x > 0.05 and env.sim.state.status[0] == 0  # ended by the function, not the engine
    env.step({a: (speeds[a], 0.0) for a in env.agents})
    assert env.sim.state.reference[0, 0] == 0.0  # a finished agent's robot is told to stop


def test_only_the_chosen_robots_are_agents_and_others_follow_their_algorithm(
        four_robots: Scenario) -> None:
    env = mimics.env.parallel_env(four_robots, agents=[1, 2], others="go_to_goal")
    env.reset(seed=0)
    assert env.possible_agents == ["robot_1", "robot_2"]
    for _ in range(20):
        env.step({"robot_1": (0.0, 0.0), "robot_2": (0.0, 0.0)})
    x = env.sim.state.pose[:, 0]
    assert x[0] > 0.2 and x[0] == x[3]  # go_to_goal drives both alike toward x = 3
    assert x[1] == 0.0 and x[2] == 0.0
    still = mimics.env.parallel_env(four_robots, agents=[1])
    still.reset(seed=0)
    for _ in range(20):
        still.step({"robot_1": (0.3, 0.0)})
    np.testing.assert_array_equal(still.sim.state.pose[0], [0.0, 0.0, 0.0])  # stands still
    assert still.sim.state.pose[1, 0] > 0.3


@pytest.mark.parametrize(("options", "actions", "message"), [
    ({}, {"robot_9": (0.1, 0.0)}, "unknown agent 'robot_9'"),
    ({}, {"robot_0": (math.nan, 0.0)}, r"actions\['robot_0'\]: expected two finite"),
    ({}, {"robot_0": (0.1, 0.0, 3.0)}, r"actions\['robot_0'\]"),
    ({"reward": lambda step: np.zeros(2)}, {"robot_0": (0.1, 0.0)}, "shape \\(4,\\)"),
])
def test_bad_actions_and_functions_are_one_line_errors(
        four_robots: Scenario, options: dict, actions: dict, message: str) -> None:
    env = mimics.env.parallel_env(four_robots, **options)
    env.reset(seed=0)
    with pytest.raises(MimicsError, match=message):
        env.step(actions)


@pytest.mark.parametrize(("options", "message"), [
    ({"observation": "image"}, "observation: expected 'dict' or 'flat'"),
    ({"heading": "left"}, "heading: expected 'relative' or 'absolute'"),
    ({"agents": [7]}, "agents: expected robot indices from 0 to 3"),
    ({"render_mode": "human"}, "render_mode"),
    ({"time": -1.0}, "time: expected a positive number"),
])
def test_bad_options_are_one_line_errors(four_robots: Scenario, options: dict,
                                         message: str) -> None:
    with pytest.raises(MimicsError, match=message):
        mimics.env.parallel_env(four_robots, **options)


def test_step_before_reset_is_an_error(four_robots: Scenario) -> None:
    with pytest.raises(MimicsError, match="call reset"):
        mimics.env.parallel_env(four_robots).step({"robot_0": (0.1, 0.0)})


def test_rgb_array_render(four_robots: Scenario) -> None:
    env = mimics.env.parallel_env(four_robots, render_mode="rgb_array")
    env.reset(seed=0)
    frame = env.render()
    assert frame.ndim == 3 and frame.shape[2] == 3 and frame.dtype == np.uint8
