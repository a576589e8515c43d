"""Seeded episodes repeat exactly; other seeds differ only where there is noise."""

from __future__ import annotations

from typing import Any

import numpy as np
from conftest import open_field

import mimics.env
from mimics.records.run_folder import load_run
from mimics.world.scenario import Scenario


def _episode(env: Any, seed: int | None, steps: int = 30) -> list[tuple[dict, dict]]:
    """Observations and rewards of ``steps`` steps of actions from a fixed generator."""
    actions = np.random.default_rng(99)
    observations, _ = env.reset(seed=seed)
    seen = [(observations, {})]
    for _ in range(steps):
        if not env.agents:
            break
        chosen = {agent: actions.uniform(env.action_space(agent).low,
                                         env.action_space(agent).high) for agent in env.agents}
        observations, rewards, *_ = env.step(chosen)
        assert all(env.observation_space(agent).contains(observation)
                   for agent, observation in observations.items())
        seen.append((observations, rewards))
    return seen


def _same(a: list[tuple[dict, dict]], b: list[tuple[dict, dict]]) -> bool:
    if len(a) != len(b):
        return False
    for (obs_a, rew_a), (obs_b, rew_b) in zip(a, b, strict=True):
        if obs_a.keys() != obs_b.keys() or rew_a != rew_b:
            return False
        if not all(np.array_equal(obs_a[k], obs_b[k]) for k in obs_a):
            return False
    return True


def test_same_seed_same_actions_same_episode(noisy_four_robots: Scenario) -> None:
    first = mimics.env.parallel_env(noisy_four_robots, observation="flat")
    second = mimics.env.parallel_env(noisy_four_robots, observation="flat")
    assert _same(_episode(first, 7), _episode(second, 7))
    # unseeded resets draw their seeds from the generator the last seed started
    assert _same(_episode(first, None), _episode(second, None))
    assert first.sim.seed == second.sim.seed != 7


def test_another_seed_changes_a_noisy_world_only(noisy_four_robots: Scenario,
                                                  four_robots: Scenario) -> None:
    noisy = mimics.env.parallel_env(noisy_four_robots, observation="flat")
    assert not _same(_episode(noisy, 1), _episode(noisy, 2))
    exact = mimics.env.parallel_env(four_robots, observation="flat")
    assert _same(_episode(exact, 1), _episode(exact, 2))


def test_nothing_is_written_without_out(four_robots: Scenario, tmp_path: Any,
                                        monkeypatch: Any) -> None:
    monkeypatch.chdir(tmp_path)
    _episode(mimics.env.parallel_env(four_robots), 0, steps=5)
    assert list(tmp_path.iterdir()) == []


def test_out_records_each_episode_as_a_run(tmp_path: Any) -> None:
    scenario = open_field([[0.0, 0.0, 0.0, 0.0, 3.0, 0.0]], time_limit=1.0)
    env = mimics.env.parallel_env(scenario, out=tmp_path)
    seen = _episode(env, 4)  # to the time limit (10 steps)
    _episode(env, 5, steps=3)  # cut short by close()
    env.close()
    full, cut = load_run(tmp_path / "episode_00000"), load_run(tmp_path / "episode_00001")
    assert full.summary["status"] == "time_limit" and full.summary["seed"] == 4
    assert cut.summary["status"] == "stopped" and cut.summary["seed"] == 5
    trajectory = full.trajectory
    final = trajectory[trajectory["time"] == trajectory["time"].max()]
    assert len(seen) == 11
    last_x = seen[-1][0]["robot_0"]["pose"][0]
    np.testing.assert_allclose(final["x"].to_numpy(), [last_x], rtol=1e-6)
