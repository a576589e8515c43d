"""A Gymnasium ``Env`` driving one robot of a scenario; the others follow an algorithm.

A thin wrapper over :class:`~mimics.interfaces.env.parallel.MimicsParallelEnv`
with a single agent: same observations, actions, rewards, seeds and records.
The other robots follow ``others`` (a built-in algorithm name such as
``"go_to_goal"``, a file, or a function/class/module) or, by default, stand
still where they are.

>>> from mimics.interfaces.env.single import SingleRobotEnv
>>> env = SingleRobotEnv("line", robots=3, robot=1, others="go_to_goal")
>>> observation, info = env.reset(seed=0)
>>> sorted(observation)
['goal', 'pose', 'scan', 'velocity']
>>> observation, reward, terminated, truncated, info = env.step(env.action_space.sample())
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, ClassVar

import gymnasium
import numpy as np

from mimics.interfaces.env.parallel import MimicsParallelEnv, agent_name
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario

#: The id under which :class:`SingleRobotEnv` is registered with Gymnasium:
#: ``gymnasium.make(GYM_ID, scenario="line", robots=3)``.
GYM_ID = "mimics/SingleRobot-v0"


class SingleRobotEnv(gymnasium.Env):
    """Robot ``robot`` of ``scenario`` as a Gymnasium environment.

    Args:
        scenario: a built-in name, a ``.py``/``.toml`` file or a Scenario.
        robot: the index of the robot the agent drives.
        others: the other robots' algorithm (default: they stand still).
        render_mode: ``None`` or ``"rgb_array"``.
        **options: the other options of :class:`MimicsParallelEnv` (``robots``,
            ``params``, ``time``, ``observation``, ``heading``, ``reward``,
            ``terminate``, ``out``).
    """

    metadata: ClassVar[dict[str, Any]] = {"render_modes": ["rgb_array"]}

    def __init__(self, scenario: str | Path | Scenario, *, robot: int = 0, others: Any = None,
                 render_mode: str | None = None, **options: Any) -> None:
        if "agents" in options:
            raise MimicsError("agents: a single-robot environment drives one robot; use robot=")
        self.multi = MimicsParallelEnv(scenario, agents=[robot], others=others,
                                       render_mode=render_mode, **options)
        self.agent = agent_name(robot)
        self.observation_space = self.multi.observation_space(self.agent)
        self.action_space = self.multi.action_space(self.agent)
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": self.multi.metadata["render_fps"]}

    def reset(self, *, seed: int | None = None,
              options: dict[str, Any] | None = None) -> tuple[Any, dict[str, Any]]:
        """Start an episode (``seed``: the engine's seed, as for the parallel env)."""
        super().reset(seed=seed)
        observations, infos = self.multi.reset(seed=seed, options=options)
        if self.agent not in observations:
            raise MimicsError(f"{self.agent} is not active at the start of the episode "
                              "(it touches a wall or another robot): pick another robot")
        return observations[self.agent], infos[self.agent]

    def step(self, action: Any) -> tuple[Any, float, bool, bool, dict[str, Any]]:
        """One step of the simulation with this robot's ``[speed, heading]`` action."""
        observations, rewards, terminations, truncations, infos = self.multi.step(
            {self.agent: action})
        agent = self.agent
        return (observations[agent], float(rewards[agent]), bool(terminations[agent]),
                bool(truncations[agent]), infos[agent])

    def render(self) -> np.ndarray | None:
        """An RGB frame of the world (``render_mode="rgb_array"``), else None."""
        return self.multi.render()

    def close(self) -> None:
        """End the current episode (its record, if any, is completed)."""
        self.multi.close()


if GYM_ID not in gymnasium.registry:  # registered once, when this module is first imported
    gymnasium.register(id=GYM_ID, entry_point=f"{__name__}:SingleRobotEnv")
