"""What an agent observes: its scan, pose, velocity and goal, as a ``Dict`` or a flat ``Box``.

Every agent's observation comes from one batched computation over the world's
arrays per step (float32 rows, one per acting robot); an agent's entries are
views into its row, so building 100 observations costs one NumPy pass and
100 slices. All values are measured ones (what the robot's own sensors
report, with its type's noise), never the ground truth:

* ``pose``: ``(x, y, theta)``, metres and radians (theta in ``[-pi, pi]``);
* ``velocity``: ``(v, w)``, m/s and rad/s;
* ``goal``: the goal in the robot's own frame, ``(ahead, left)`` in metres
  (``(0, 0)`` for a robot without a goal);
* ``scan``: the ranger's distances per beam, right to left, in
  ``[0, max_range]``.

The flat layout is ``[pose (3), velocity (2), goal (2), scan (beams)]``: the
scan comes last so that robots of types with different beam counts share the
first seven columns.
"""

from __future__ import annotations

import functools
import math
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from gymnasium import spaces

from mimics.world.errors import MimicsError

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation
    from mimics.world.scenario import Scenario

ObservationKind = Literal["dict", "flat"]
OBSERVATION_KINDS = ("dict", "flat")
HEAD = 7  # columns before the scan in the flat layout: pose 3, velocity 2, goal 2


def check_kind(kind: Any) -> ObservationKind:
    """``kind`` if it is ``"dict"`` or ``"flat"``; a one-line error otherwise."""
    if kind not in OBSERVATION_KINDS:
        raise MimicsError(f"observation: expected 'dict' or 'flat', got {kind!r}")
    return kind


def head_bounds(scenario: Scenario) -> tuple[np.ndarray, np.ndarray]:
    """Per robot, the bounds ``(n, 7)`` of the flat layout's first seven columns.

    Positions: the map's bounds widened by its larger side (a robot is
    deactivated a step after leaving them); speed and turn rate: twice the
    type's top values (plus the initial speed); the goal: the diagonal of the
    box holding the widened map and the goals. Observations are clipped to
    them, which only positioning noise could need.
    """
    xmin, ymin, xmax, ymax = scenario.map.bounds
    margin = max(xmax - xmin, ymax - ymin, 1.0)
    goals = scenario.goals[~np.isnan(scenario.goals[:, 0])]
    xs = [xmin - margin, xmax + margin, *goals[:, 0].tolist()]
    ys = [ymin - margin, ymax + margin, *goals[:, 1].tolist()]
    reach = math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    n = scenario.robot_count
    types = [scenario.robot_type(i) for i in range(n)]
    speed = np.array([2 * t.max_speed for t in types]) + np.abs(scenario.stages[:, 3])
    turn = np.array([2 * t.kw for t in types])
    high = np.column_stack([np.full(n, xmax + margin), np.full(n, ymax + margin),
                            np.full(n, math.pi), speed, turn, np.full(n, reach),
                            np.full(n, reach)])
    low = -high
    low[:, 0], low[:, 1] = xmin - margin, ymin - margin
    return low.astype(np.float32), high.astype(np.float32)


def observation_space(kind: ObservationKind, low: np.ndarray, high: np.ndarray, beams: int,
                      max_range: float) -> spaces.Space:
    """One robot's observation space: its seven ``low``/``high`` bounds and its ranger's."""
    box = functools.partial(spaces.Box, dtype=np.float32)
    if kind == "dict":
        return spaces.Dict({"pose": box(low[0:3], high[0:3]),
                            "velocity": box(low[3:5], high[3:5]),
                            "goal": box(low[5:HEAD], high[5:HEAD]),
                            "scan": box(0.0, np.float32(max_range), shape=(beams,))})
    return box(np.concatenate([low, np.zeros(beams, dtype=np.float32)]),
               np.concatenate([high, np.full(beams, max_range, dtype=np.float32)]))


def observation_rows(sim: Simulation, ids: np.ndarray, low: np.ndarray,
                     high: np.ndarray) -> np.ndarray:
    """The flat layout for robots ``ids``, one float32 row each (``(k, 7 + B)``).

    ``low`` and ``high`` are the ``(n, 7)`` bounds of :func:`head_bounds`.

    A robot with fewer beams than the widest type has NaN in the columns past
    its own scan; :class:`ObservationMaker` never hands those columns out.
    """
    state = sim.state
    pose = state.measured_pose[ids]
    x, y, theta = pose[:, 0], pose[:, 1], pose[:, 2]
    rows = np.empty((len(ids), HEAD + state.scan.shape[1]), dtype=np.float32)
    rows[:, 0] = x
    rows[:, 1] = y
    rows[:, 2] = np.arctan2(np.sin(theta), np.cos(theta))  # the engine's theta, in [-pi, pi]
    rows[:, 3:5] = state.measured_velocity[ids]
    goal = state.goal[ids]
    dx, dy = goal[:, 0] - x, goal[:, 1] - y
    cos, sin = np.cos(theta), np.sin(theta)
    rows[:, 5] = cos * dx + sin * dy  # ahead
    rows[:, 6] = cos * dy - sin * dx  # to the left
    rows[:, 5:7][np.isnan(goal)] = 0.0  # no goal: (0, 0)
    np.clip(rows[:, :HEAD], low[ids], high[ids], out=rows[:, :HEAD])
    rows[:, HEAD:] = state.scan[ids]
    return rows


class ObservationMaker:
    """Builds agents' observations from the world, in the layout ``kind``.

    Args:
        kind: ``"dict"`` or ``"flat"``.
        scenario: the scenario (its robots' types and the bounds of the values).
    """

    def __init__(self, kind: ObservationKind, scenario: Scenario) -> None:
        self.kind = check_kind(kind)
        self.low, self.high = head_bounds(scenario)
        types = [scenario.robot_type(i) for i in range(scenario.robot_count)]
        self.spaces = [observation_space(kind, self.low[i], self.high[i], t.ranger.beams,
                                         t.ranger.range) for i, t in enumerate(types)]
        self._ends = [HEAD + t.ranger.beams for t in types]
        self._uniform = len(set(self._ends)) <= 1  # one beam count: whole rows, no slicing

    def make(self, sim: Simulation, agents: list[str], ids: np.ndarray) -> dict[str, Any]:
        """Observations of ``agents`` (robots ``ids``, same order)."""
        rows = observation_rows(sim, ids, self.low, self.high)
        if self._uniform:  # iterating a 2-D array gives its rows as views, at C speed
            if self.kind == "flat":
                return dict(zip(agents, rows, strict=True))
            scans: Any = rows[:, HEAD:]
        else:
            ends = [self._ends[i] for i in ids.tolist()]
            if self.kind == "flat":
                return {agent: row[:end] for agent, row, end in zip(agents, rows, ends,
                                                                    strict=True)}
            scans = [row[HEAD:end] for row, end in zip(rows, ends, strict=True)]
        return {agent: {"pose": pose, "velocity": velocity, "goal": goal, "scan": scan}
                for agent, pose, velocity, goal, scan in zip(
                    agents, rows[:, 0:3], rows[:, 3:5], rows[:, 5:HEAD], scans, strict=True)}
