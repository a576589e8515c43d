"""The reinforcement-learning loop on a mimics scenario, with a scripted or a random policy.

    python examples/rl_loop/run.py [--policy scripted|random] [--episodes 3]
                                   [--scenario circle_swap] [--robots 8] [--seed 0]
                                   [--time SECONDS]

Nothing is trained: the policy is a rule (steer toward the goal the agent
observes, at full speed) or random actions, to show the loop a learner
plugs into: reset, then step with one action per live agent until no agent
is left, adding up each agent's rewards. Prints one line per episode.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

import numpy as np

import mimics.env

CAUTION = 0.8  # m: closer than this ahead, the scripted policy gives way...
STOP = 0.3  # m: ...and stops this close


def scripted(observation: dict[str, np.ndarray], top_speed: float) -> np.ndarray:
    """Steer toward the goal (given in the robot's own frame); keep right of what is ahead.

    The scan runs from right (-90 degrees) to left (+90): its middle two
    thirds (+-60 degrees) are what lies ahead. Something within ``CAUTION`` m
    there: slow down and turn right, so that robots meeting head-on pass each
    other as on a road.
    """
    ahead, left = observation["goal"]
    scan = observation["scan"]
    sixth = len(scan) // 6
    nearest = float(scan[sixth:len(scan) - sixth].min())
    if nearest < CAUTION:
        speed = top_speed * max(nearest - STOP, 0.0) / CAUTION
        return np.array([speed, -0.5], dtype=np.float32)  # a relative turn: to the right
    return np.array([top_speed, math.atan2(left, ahead)], dtype=np.float32)


def run_episode(env: Any, policy: str, seed: int,
                rng: np.random.Generator) -> tuple[dict[str, float], dict[str, str]]:
    """One episode; returns each agent's return and how its episode ended."""
    observations, _ = env.reset(seed=seed)
    returns = dict.fromkeys(env.agents, 0.0)
    endings = dict.fromkeys(env.agents, "running")
    while env.agents:
        actions = {}
        for agent in env.agents:
            space = env.action_space(agent)
            if policy == "scripted":
                actions[agent] = scripted(observations[agent], float(space.high[0]))
            else:
                actions[agent] = rng.uniform(space.low, space.high).astype(np.float32)
        observations, rewards, terminations, truncations, infos = env.step(actions)
        for agent, reward in rewards.items():
            returns[agent] += reward
            if terminations[agent]:
                endings[agent] = infos[agent]["status"]
            elif truncations[agent]:
                endings[agent] = "time_limit"
    return returns, endings


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--policy", choices=["scripted", "random"], default="scripted")
    parser.add_argument("--episodes", type=int, default=3)
    parser.add_argument("--scenario", default="circle_swap")
    parser.add_argument("--robots", type=int, default=8)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--time", type=float, default=None,
                        help="simulated seconds per episode (default: the scenario's)")
    args = parser.parse_args(argv)
    env = mimics.env.parallel_env(args.scenario, robots=args.robots, time=args.time)
    rng = np.random.default_rng(args.seed)
    for episode in range(args.episodes):
        returns, endings = run_episode(env, args.policy, args.seed + episode, rng)
        counts = {ending: list(endings.values()).count(ending) for ending in sorted(
            set(endings.values()))}
        print(f"episode {episode}: mean return {np.mean(list(returns.values())):.3f} over "
              f"{len(returns)} agents; " + ", ".join(f"{k} {v}" for k, v in counts.items()),
              flush=True)
    env.close()


if __name__ == "__main__":
    main()
