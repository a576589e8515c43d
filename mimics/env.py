"""Learning environments over mimics simulations (needs ``pip install 'mimics-sim[rl]'``).

``parallel_env`` gives a PettingZoo ``ParallelEnv`` whose agents are the
robots; ``single_robot_env`` (also ``gym_env``) a Gymnasium ``Env`` driving
one robot. PettingZoo and Gymnasium are imported on the first call, not
with this module. See docs/how-to/learning-environments.md.

>>> import mimics.env
>>> env = mimics.env.parallel_env("line", robots=2)
>>> observations, infos = env.reset(seed=0)
>>> env.agents
['robot_0', 'robot_1']
"""

from __future__ import annotations

import importlib
from pathlib import Path
from typing import TYPE_CHECKING, Any

from mimics.world.errors import MimicsError

if TYPE_CHECKING:
    from mimics.interfaces.env.parallel import MimicsParallelEnv
    from mimics.interfaces.env.rewards import GoalReward, Transition
    from mimics.interfaces.env.single import SingleRobotEnv
    from mimics.world.scenario import Scenario

__all__ = ["GoalReward", "MimicsParallelEnv", "SingleRobotEnv", "Transition", "gym_env",
           "parallel_env", "single_robot_env"]
_CLASSES = {"GoalReward": "rewards", "Transition": "rewards", "MimicsParallelEnv": "parallel",
            "SingleRobotEnv": "single"}


def _module(name: str) -> Any:
    """``mimics.interfaces.env.<name>``, with a one-line hint when the extra is missing."""
    try:
        return importlib.import_module(f"mimics.interfaces.env.{name}")
    except ModuleNotFoundError as exc:
        if exc.name in ("pettingzoo", "gymnasium"):
            raise MimicsError(f"mimics.env needs {exc.name}: "
                              "pip install 'mimics-sim[rl]'") from None
        raise


def parallel_env(scenario: str | Path | Scenario, **options: Any) -> MimicsParallelEnv:
    """A PettingZoo ``ParallelEnv`` of ``scenario``; every robot is an agent.

    ``options`` are those of :class:`mimics.interfaces.env.parallel.MimicsParallelEnv`:
    ``robots``, ``params``, ``time``, ``observation`` (``"dict"``/``"flat"``),
    ``heading`` (``"relative"``/``"absolute"``), ``reward``, ``terminate``,
    ``agents``, ``others``, ``out``, ``render_mode``.
    """
    return _module("parallel").MimicsParallelEnv(scenario, **options)


def single_robot_env(scenario: str | Path | Scenario, **options: Any) -> SingleRobotEnv:
    """A Gymnasium ``Env`` driving robot ``robot`` (default 0) of ``scenario``.

    ``options``: ``robot``, ``others`` (the other robots' algorithm; default
    they stand still) and the options of :func:`parallel_env` but ``agents``.
    """
    return _module("single").SingleRobotEnv(scenario, **options)


gym_env = single_robot_env


def __getattr__(name: str) -> Any:
    if name in _CLASSES:  # imported on first use, like the functions' libraries
        return getattr(_module(_CLASSES[name]), name)
    raise AttributeError(f"module 'mimics.env' has no attribute {name!r}")
