"""What an agent does: a speed and a heading reference, fed to the engine as an algorithm.

An action is a ``Box`` of two float32 numbers:

* ``speed``: the speed reference in m/s, in ``[-max_speed, max_speed]`` of
  the robot's type (``RobotType.max_speed``, its ``kv``); negative drives
  backwards;
* ``heading``: with ``heading="relative"`` (the default), a turn in radians
  in ``[-pi, pi]`` added to the robot's measured heading (0 keeps the
  current heading); with ``heading="absolute"``, the heading reference
  itself in ``[-pi, pi]`` (0 faces +x).

The robot's speed and heading PID loops and its dynamics do the rest, as for
any algorithm. Actions outside the box are clipped to it; an action that is
not two finite numbers is an error naming the agent.

The engine runs the actions through :class:`PolicyController`, a controller of
the engine's own contract (:mod:`mimics.engine.user_code.controllers`): each step the
simulation asks it for references and it returns what the environment set,
so the engine's one step loop drives everything.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from gymnasium import spaces

from mimics.engine.user_code import Controller, UserFailure
from mimics.world.errors import MimicsError

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation

HeadingMode = Literal["relative", "absolute"]
HEADING_MODES = ("relative", "absolute")


def check_heading_mode(mode: Any) -> HeadingMode:
    """``mode`` if it is ``"relative"`` or ``"absolute"``; a one-line error otherwise."""
    if mode not in HEADING_MODES:
        raise MimicsError(f"heading: expected 'relative' or 'absolute', got {mode!r}")
    return mode


def action_space(max_speed: float) -> spaces.Box:
    """``[speed, heading]`` for a robot of top speed ``max_speed`` (m/s)."""
    low = np.array([-max_speed, -math.pi], dtype=np.float32)
    high = np.array([max_speed, math.pi], dtype=np.float32)
    return spaces.Box(low, high, dtype=np.float32)


def actions_to_rows(actions: dict[str, Any], index: dict[str, int],
                    live: set[str]) -> tuple[np.ndarray, np.ndarray]:
    """The robots and ``(k, 2)`` float64 actions of the live agents in ``actions``.

    Actions of agents that have already finished are ignored (wrappers that
    keep stepping dead agents send them); unknown names are errors.
    """
    names = [agent for agent in actions if agent in live]
    if len(names) != len(actions):
        unknown = next((agent for agent in actions if agent not in index), None)
        if unknown is not None:
            raise MimicsError(f"actions: unknown agent {unknown!r} (agents are named "
                              f"robot_0 ... robot_{len(index) - 1})")
    if not names:
        return np.zeros(0, dtype=np.int64), np.zeros((0, 2))
    rows = list(actions.values()) if len(names) == len(actions) else [actions[a] for a in names]
    try:
        values = np.asarray(rows, dtype=np.float64).reshape(len(names), 2)
    except (TypeError, ValueError):
        values = None
    if values is None or not np.all(np.isfinite(values)):
        bad = next(agent for agent in names if not _two_finite_numbers(actions[agent]))
        raise MimicsError(f"actions[{bad!r}]: expected two finite numbers (speed, heading), "
                          f"got {actions[bad]!r}")
    return np.array([index[agent] for agent in names], dtype=np.int64), values


def _two_finite_numbers(action: Any) -> bool:
    try:
        values = np.asarray(action, dtype=np.float64)
    except (TypeError, ValueError):
        return False
    return values.shape == (2,) and bool(np.all(np.isfinite(values)))


class PolicyController(Controller):
    """Drives the agents' robots with the actions set by the environment.

    Robots not controlled by the environment follow ``others`` (any algorithm
    controller), or, without one, stand still (speed 0, heading held).
    Controlled robots without an action this step stand still too.

    Args:
        controlled: ``(n,)`` mask of the robots the environment controls.
        max_speed: ``(n,)`` each robot's top speed, the bound of its speed action.
        heading: ``"relative"`` or ``"absolute"`` (see the module's docstring).
        others: the controller of the robots the environment does not control.
    """

    name = "external_policy"
    is_team = True

    def __init__(self, controlled: np.ndarray, max_speed: np.ndarray, heading: HeadingMode,
                 others: Controller | None = None) -> None:
        self.controlled = controlled
        self.max_speed = max_speed
        self.heading = check_heading_mode(heading)
        self.others = others
        self.all_controlled = bool(np.all(controlled))
        self.speed = np.zeros(len(controlled))  # this step's references
        self.turn = np.zeros(len(controlled))  # heading action (relative or absolute)
        self.given = np.zeros(len(controlled), dtype=bool)  # which robots have an action

    def set_actions(self, robots: np.ndarray, values: np.ndarray) -> np.ndarray:
        """Store the actions of ``robots`` for the next step; returns them clipped (k, 2)."""
        speed = np.clip(values[:, 0], -self.max_speed[robots], self.max_speed[robots])
        turn = np.clip(values[:, 1], -math.pi, math.pi)
        self.given[:] = False
        self.given[robots] = True
        self.speed[robots] = speed
        self.turn[robots] = turn
        return np.column_stack([speed, turn])

    def reset(self, sim: Simulation) -> list[UserFailure]:
        self.given[:] = False
        return self.others.reset(sim) if self.others is not None else []

    def compute(self, sim: Simulation, ids: np.ndarray) -> list[UserFailure]:
        state = sim.state
        failures: list[UserFailure] = []
        mine = ids if self.all_controlled else ids[self.controlled[ids]]
        if not self.all_controlled:
            theirs = ids[~self.controlled[ids]]
            if self.others is not None and theirs.size:
                failures = self.others.compute(sim, theirs)
            elif theirs.size:
                state.reference[theirs, 0] = 0.0
                state.reference[theirs, 1] = state.measured_pose[theirs, 2]
        heading = state.measured_pose[mine, 2]
        given = self.given[mine]
        turn = self.turn[mine]
        state.reference[mine, 0] = np.where(given, self.speed[mine], 0.0)
        if self.heading == "relative":
            state.reference[mine, 1] = heading + np.where(given, turn, 0.0)
        else:
            state.reference[mine, 1] = np.where(given, turn, heading)
        state.user_time[mine] = 0.0  # the policy's time is spent outside the step
        return failures
