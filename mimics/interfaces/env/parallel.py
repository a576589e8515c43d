"""A PettingZoo ``ParallelEnv`` over one mimics simulation: every robot is an agent.

The environment owns no step loop of its own: each ``step(actions)`` stores
the actions in a :class:`~mimics.interfaces.env.actions.PolicyController` (the
engine's controller contract) and calls the engine's ``Simulation.step()``
once, which senses, asks that controller for references, moves the robots,
checks collisions, goals and escapes and deactivates robots, exactly as
``mimics run`` does. Observations, rewards and terminations are then read
from the world's arrays (:mod:`.observations`, :mod:`.rewards`).

* Agents are ``robot_0`` ... ``robot_{n-1}`` (the robots' indices), or the
  subset given in ``agents``; the other robots follow ``others``.
* An agent terminates when the engine deactivates its robot (goal reached,
  collision, escape, deadlock) or the termination function says so; its
  ``infos`` entry then has ``"status"``. All live agents are truncated when
  the simulated time limit is reached.
* ``reset(seed=s)`` runs the engine with seed ``s``: the episode is the run
  ``mimics run SCENARIO --seed s`` would make with the same actions. Later
  ``reset()`` calls without a seed draw the next seeds from a generator
  seeded by ``s``.
* Nothing is written unless ``out`` is given: then episode ``k`` is
  recorded, like ``mimics run --out``, into ``out/episode_0000k/``.

>>> from mimics.interfaces.env.parallel import MimicsParallelEnv
>>> env = MimicsParallelEnv("line", robots=2, observation="flat")
>>> observations, infos = env.reset(seed=1)
>>> sorted(observations), observations["robot_0"].shape
(['robot_0', 'robot_1'], (277,))
>>> actions = {agent: env.action_space(agent).high * [1, 0] for agent in env.agents}
>>> observations, rewards, terminations, truncations, infos = env.step(actions)
>>> round(rewards["robot_0"], 3) > 0  # it moved toward its goal
True
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, ClassVar

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv

from mimics.catalog import find_algorithm
from mimics.engine.simulation import Simulation
from mimics.engine.state import Status
from mimics.engine.user_code import Controller, controller_from
from mimics.interfaces.env.actions import (
    HeadingMode,
    PolicyController,
    action_space,
    actions_to_rows,
)
from mimics.interfaces.env.observations import ObservationKind, ObservationMaker
from mimics.interfaces.env.rewards import (
    GoalReward,
    RewardFunction,
    TerminationFunction,
    Transition,
)
from mimics.records.recorder import RunRecorder
from mimics.records.runner import build_scenario, prepare
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario

_ACTIVE, _REACHED = int(Status.ACTIVE), int(Status.REACHED_GOAL)
_COLLIDED, _ESCAPED = int(Status.COLLIDED), int(Status.ESCAPED)
_TRUNCATING = ("time_limit", "wall_limit")  # end states that cut live agents short


def agent_name(robot: int) -> str:
    """The agent of robot ``robot``."""
    return f"robot_{robot}"


def others_controller(others: Any) -> Controller | None:
    """The controller of the robots the environment does not drive (None: they stand still)."""
    if others is None:
        return None
    if isinstance(others, str | Path):
        name, others = find_algorithm(others)
        return controller_from(others, name)
    return controller_from(others)


class MimicsParallelEnv(ParallelEnv):
    """The robots of a scenario as the agents of a PettingZoo ``ParallelEnv``.

    Args:
        scenario: a built-in name (``"cave"``), a ``.py``/``.toml`` file or a Scenario.
        robots: shorthand for the scenario parameter ``robots``.
        params: other scenario parameters.
        time: simulated seconds per episode (default: the scenario's time limit);
            reaching it truncates the live agents.
        observation: ``"dict"`` (pose, velocity, goal, scan) or ``"flat"`` (one Box).
        heading: the heading action: ``"relative"`` (a turn from the current
            heading) or ``"absolute"`` (see :mod:`.actions`).
        reward: ``f(Transition) -> (n,)`` rewards (default :class:`GoalReward`).
        terminate: ``f(Transition) -> (n,)`` booleans ending agents' episodes
            besides the engine's deactivations (default: none).
        agents: the robots the environment drives (default: all).
        others: the algorithm of the other robots (a built-in name, a file, or
            a function/class/module); default: they stand still.
        out: a folder in which each episode is recorded; default: nothing is written.
        render_mode: ``None`` or ``"rgb_array"``.
    """

    metadata: ClassVar[dict[str, Any]] = {"name": "mimics_v0", "render_modes": ["rgb_array"],
                                          "is_parallelizable": True}

    def __init__(self, scenario: str | Path | Scenario, *, robots: int | None = None,
                 params: dict[str, Any] | None = None, time: float | None = None,
                 observation: ObservationKind = "dict", heading: HeadingMode = "relative",
                 reward: RewardFunction | None = None,
                 terminate: TerminationFunction | None = None,
                 agents: list[int] | None = None, others: Any = None,
                 out: str | Path | None = None, render_mode: str | None = None) -> None:
        if time is not None and (isinstance(time, bool) or not isinstance(time, int | float)
                                 or not time > 0):
            raise MimicsError(f"time: expected a positive number of simulated seconds, "
                              f"got {time!r}")
        self.scenario = build_scenario(scenario, robots=robots, params=params)
        n = self.scenario.robot_count
        types = [self.scenario.robot_type(i) for i in range(n)]
        controlled = np.zeros(n, dtype=bool)
        chosen = list(range(n)) if agents is None else [_robot_id(r, n) for r in agents]
        controlled[chosen] = True
        max_speed = np.array([t.max_speed for t in types])
        self.policy = PolicyController(controlled, max_speed, heading, others_controller(others))
        self.observations = ObservationMaker(observation, self.scenario)
        if render_mode not in (None, "rgb_array"):
            raise MimicsError(f"render_mode: expected None or 'rgb_array', got {render_mode!r}")
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": round(1 / self.scenario.settings.dt)}
        self.time = time
        self.reward = GoalReward() if reward is None else reward
        self.terminate = terminate
        self.out = None if out is None else Path(out)
        self.possible_agents = [agent_name(i) for i in sorted(set(chosen))]
        self.agents: list[str] = []
        self._index = {agent_name(i): i for i in range(n) if controlled[i]}
        self._observation_spaces = {agent_name(i): self.observations.spaces[i]
                                    for i in range(n) if controlled[i]}
        self._action_spaces = {agent_name(i): action_space(types[i].max_speed)
                               for i in range(n) if controlled[i]}
        self.sim: Simulation | None = None
        self.episodes = 0
        self._seeds: np.random.Generator | None = None
        self._ids = np.zeros(0, dtype=np.int64)
        self._recorder: RunRecorder | None = None
        self._renderer: Any = None

    def observation_space(self, agent: str) -> spaces.Space:
        """The observation space of ``agent`` (the same object every call)."""
        return self._observation_spaces[agent]

    def action_space(self, agent: str) -> spaces.Box:
        """The action space of ``agent``: ``[speed, heading]`` (the same object every call)."""
        return self._action_spaces[agent]

    def reset(self, seed: int | None = None,
              options: dict[str, Any] | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
        """Start an episode; returns the live agents' observations and infos.

        Args:
            seed: the engine's seed for this episode (and the seed of the
                generator that picks later episodes' seeds).
            options: accepted for the API's sake; not used.
        """
        self._finish_episode()
        if seed is not None:
            self._seeds = np.random.default_rng(seed)
            episode_seed = int(seed)
        else:
            if self._seeds is None:
                self._seeds = np.random.default_rng()
            episode_seed = int(self._seeds.integers(2**31))
        observers: tuple[Any, ...] = ()
        if self.out is not None:
            self._recorder = RunRecorder(self.out / f"episode_{self.episodes:05d}",
                                         robot_logs="off")
            observers = (self._recorder,)
        self.episodes += 1
        self.sim = prepare(self.scenario, self.policy, seed=episode_seed, time=self.time,
                           observers=observers)
        self.sim.start()
        if self.sim.status == "error":
            raise MimicsError(f"the other robots' algorithm failed: {self.sim.error}")
        active = self.sim.state.active
        self._ids = np.array([i for i in self._index.values() if active[i]], dtype=np.int64)
        self.agents = [agent_name(i) for i in self._ids.tolist()]
        observations = self.observations.make(self.sim, self.agents, self._ids)
        return observations, {agent: {} for agent in self.agents}

    def step(self, actions: dict[str, Any]) -> tuple[dict[str, Any], dict[str, float],
                                                      dict[str, bool], dict[str, bool],
                                                      dict[str, Any]]:
        """Apply the live agents' actions for one step of the simulation.

        Returns:
            observations, rewards, terminations, truncations and infos of the
            agents live before the step; finished ones leave ``agents``.
        """
        sim = self.sim
        if sim is None or not self.agents:
            raise MimicsError("step: no episode is running; call reset() first")
        agents, ids = self.agents, self._ids
        robots, values = actions_to_rows(actions, self._index, set(agents))
        applied = self.policy.set_actions(robots, values)
        state = sim.state
        before = state.goal_distance()
        was_active = state.active
        sim.step()
        if sim.status == "error":
            raise MimicsError(f"the other robots' algorithm failed: {sim.error}")
        status = state.status
        ended = was_active & (status != _ACTIVE)
        taken = np.full((state.n, 2), np.nan)
        taken[robots] = applied
        transition = Transition(sim=sim, ids=ids, actions=taken, distance_before=before,
                                distance_after=state.goal_distance(),
                                reached=ended & (status == _REACHED),
                                collided=ended & (status == _COLLIDED),
                                escaped=ended & (status == _ESCAPED))
        rewards = _per_robot(self.reward(transition), state.n, "reward")[ids]
        finished = status[ids] != _ACTIVE
        if self.terminate is not None:
            finished |= _per_robot(self.terminate(transition), state.n, "terminate",
                                   dtype=bool)[ids]
        truncated = ~finished if sim.status in _TRUNCATING else np.zeros(len(ids), dtype=bool)
        observations = self.observations.make(sim, agents, ids)
        infos: dict[str, Any] = {agent: {} for agent in agents}
        for k in np.flatnonzero(finished).tolist():
            infos[agents[k]] = {"status": Status(int(status[ids[k]])).label}
        keep = ~(finished | truncated)  # a run that ended otherwise has no active robot
        self._ids = ids[keep]
        self.agents = [agent for agent, live in zip(agents, keep.tolist(), strict=True) if live]
        return (observations, dict(zip(agents, rewards.tolist(), strict=True)),
                dict(zip(agents, finished.tolist(), strict=True)),
                dict(zip(agents, truncated.tolist(), strict=True)), infos)

    def render(self) -> np.ndarray | None:
        """An RGB frame of the world (``render_mode="rgb_array"``), else None."""
        if self.render_mode != "rgb_array" or self.sim is None:
            return None
        from mimics.interfaces.render import WorldRenderer

        sim = self.sim
        if self._renderer is None:
            types = sim.types
            self._renderer = WorldRenderer.create(self.scenario.map.segments,
                                                  self.scenario.map.bounds, types.half_length,
                                                  types.half_width, self.scenario.goals)
        self._renderer.update(sim.state.pose, sim.state.status, sim.state.time)
        return self._renderer.to_rgb()

    def close(self) -> None:
        """End the current episode (its record, if any, is completed)."""
        self._finish_episode()
        self.sim = None
        self.agents = []

    def _finish_episode(self) -> None:
        """Complete the record of an episode left before the run ended, as ``stopped``."""
        recorder, sim = self._recorder, self.sim
        self._recorder = None
        if recorder is None or sim is None or recorder.finished:
            return
        sim.status = "stopped"
        recorder.on_end(sim, sim.result())


def _robot_id(robot: Any, n: int) -> int:
    if isinstance(robot, bool) or not isinstance(robot, int | np.integer) or not 0 <= robot < n:
        raise MimicsError(f"agents: expected robot indices from 0 to {n - 1}, got {robot!r}")
    return int(robot)


def _per_robot(values: Any, n: int, what: str, dtype: type = np.float64) -> np.ndarray:
    """A user function's output as ``(n,)`` of ``dtype``; a one-line error otherwise."""
    array = np.asarray(values, dtype=dtype)
    if array.shape != (n,):
        raise MimicsError(f"{what}: the function must return one value per robot, shape "
                          f"({n},); got shape {array.shape}")
    return array


def parallel_env(scenario: str | Path | Scenario, **options: Any) -> MimicsParallelEnv:
    """A :class:`MimicsParallelEnv` of ``scenario`` (PettingZoo's usual factory name)."""
    return MimicsParallelEnv(scenario, **options)
