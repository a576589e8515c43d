"""Rewards and terminations: what one step did, and the default reward.

A reward function takes a :class:`Transition` (arrays over all robots,
indexed by robot id) and returns one reward per robot, ``(n,)``; only the rows
of the robots that acted are used. A termination function takes the same and
returns a boolean ``(n,)``: robots it marks end their episode (on top of the
ones the engine deactivated: goal reached, collision, escape, deadlock).

>>> import numpy as np
>>> step = Transition(sim=None, ids=np.array([0, 1]), actions=np.zeros((2, 2)),
...                   distance_before=np.array([5.0, np.nan]),
...                   distance_after=np.array([4.5, np.nan]),
...                   reached=np.array([False, False]), collided=np.array([False, True]),
...                   escaped=np.array([False, False]))
>>> GoalReward()(step).tolist()
[0.5, -10.0]
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation


@dataclass(frozen=True)
class Transition:
    """What one environment step did; every array has one row per robot of the scenario.

    Attributes:
        sim: the simulation after the step (read anything else from it:
            ``sim.state.pose``, ``sim.state.scan``, ``sim.state.time``...).
        ids: the robots that acted this step (the live agents' robots).
        actions: ``(n, 2)`` the actions applied (clipped; NaN for robots that
            did not act).
        distance_before: distance from each robot to its goal before the
            step (m, true pose; NaN without a goal).
        distance_after: the same after the step.
        reached: robots that reached their goal this step.
        collided: robots that collided this step.
        escaped: robots that left the map this step.
    """

    sim: Simulation | None
    ids: np.ndarray
    actions: np.ndarray
    distance_before: np.ndarray
    distance_after: np.ndarray
    reached: np.ndarray
    collided: np.ndarray
    escaped: np.ndarray

    @property
    def progress(self) -> np.ndarray:
        """Metres gained toward the goal this step (0 for robots without a goal)."""
        return np.nan_to_num(self.distance_before - self.distance_after, nan=0.0)


RewardFunction = Callable[[Transition], np.ndarray]
TerminationFunction = Callable[[Transition], np.ndarray]


@dataclass(frozen=True)
class GoalReward:
    """The default reward: progress to the goal, a bonus at it, penalties for crashes.

    reward = ``progress`` x metres gained toward the goal this step
    + ``goal`` on reaching it - ``collision`` on colliding - ``escape`` on
    leaving the map. Robots without a goal get only the penalties.
    """

    progress: float = 1.0
    goal: float = 10.0
    collision: float = 10.0
    escape: float = 10.0

    def __call__(self, step: Transition) -> np.ndarray:
        """Rewards ``(n,)`` of one step."""
        return (self.progress * step.progress + self.goal * step.reached
                - self.collision * step.collided - self.escape * step.escaped)
