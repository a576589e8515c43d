"""What a run produced: events as they happen, and the counts at the end."""

from __future__ import annotations

import hashlib
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from mimics.engine.state import Status, WorldState


@dataclass(frozen=True)
class Event:
    """Something that happened to a robot at a simulated time.

    ``kind`` is one of: reached_goal, collision, escaped, deadlock, deadlock_end,
    livelock, livelock_end, exception. ``other`` is the robot hit in a
    robot-robot collision (-1 for a wall, -2 when not applicable).
    """

    time: float
    robot: int
    kind: str
    detail: str = ""
    other: int = -2
    start: float = float("nan")  # when a stall began
    traceback: str = ""


class TimingStats:
    """Streaming statistics of user-code call times, in bounded memory.

    Mean and max are exact; percentiles come from a log-spaced histogram
    (bins 2% wide), accurate to about 1%.
    """

    _EDGES = np.geomspace(1e-8, 1e3, 1281)
    _HELD = 4096  # call times held before they are binned, all at once

    def __init__(self) -> None:
        self.count = 0
        self.total = 0.0
        self.maximum = 0.0
        self._histogram = np.zeros(len(self._EDGES) + 1, dtype=np.int64)
        self._held = np.empty(self._HELD)
        self._held_count = 0

    def add(self, seconds: np.ndarray) -> None:
        """Record a batch of call times (s)."""
        size = seconds.size
        if size == 0:
            return
        self.count += size
        if size <= 16:  # a few robots: Python's sum and max cost less than NumPy's calls
            values = seconds.tolist()
            self.total += sum(values)
            self.maximum = max(self.maximum, *values)
        else:
            self.total += float(np.add.reduce(seconds))  # = seconds.sum(), minus its wrappers
            self.maximum = max(self.maximum, float(np.maximum.reduce(seconds)))
        # binned in batches: a search and a full-length bincount per step cost more
        # than the step of a few robots; the histogram ends the same
        if self._held_count + size > self._HELD:
            self._bin_held()
        if size > self._HELD:
            self._bin(seconds)
            return
        self._held[self._held_count:self._held_count + size] = seconds
        self._held_count += size

    def _bin(self, seconds: np.ndarray) -> None:
        bins = np.searchsorted(self._EDGES, seconds)
        self._histogram += np.bincount(bins, minlength=len(self._histogram))

    def _bin_held(self) -> None:
        if self._held_count:
            self._bin(self._held[:self._held_count])
            self._held_count = 0

    def percentile(self, q: float) -> float:
        """The q-th percentile (0-100) of call times (s)."""
        if self.count == 0:
            return 0.0
        self._bin_held()
        rank = np.searchsorted(np.cumsum(self._histogram), q / 100 * self.count)
        rank = min(int(rank), len(self._EDGES) - 1)
        return float(min(self._EDGES[rank], self.maximum))

    def summary(self) -> dict[str, float | int]:
        """Calls, mean, p95 and max (s)."""
        return {"calls": self.count, "mean": self.total / self.count if self.count else 0.0,
                "p95": self.percentile(95), "max": self.maximum}


@dataclass
class RunResult:
    """The outcome of one simulation (``summary()`` is what summary.json holds)."""

    status: str
    scenario: str
    algorithm: str
    seed: int
    robots: int
    sim_time: float
    wall_time: float
    steps: int
    final_status: np.ndarray
    collided_with: np.ndarray
    goal_time: np.ndarray
    path_length: np.ndarray
    start_goal_distance: np.ndarray
    ever_deadlocked: np.ndarray
    ever_livelocked: np.ndarray
    events: list[Event] = field(default_factory=list)
    user_timing: dict[str, float | int] = field(default_factory=dict)
    parameters: dict[str, Any] = field(default_factory=dict)
    error: str = ""
    trajectory_digest: str = ""  # Simulation.run_digest: poses of every step and outcomes
    compile_time: float = 0.0  # s spent compiling kernels during the run (not in wall_time)
    has_goal: np.ndarray | None = None  # (n,) robots with a goal at the end (None: unknown)
    time_limit: float = float("nan")  # the run's horizon (s): a non-arrival counts as this
    #: (n,) robots stalled at least once (``on_collision = "stall"``); None: collisions
    #: deactivate (the default), and no robot stalls
    ever_stalled: np.ndarray | None = None

    def count(self, status: Status) -> int:
        """Robots whose final status is ``status``."""
        return int(np.sum(self.final_status == status))

    @property
    def reached_goal(self) -> int:
        """Robots that reached their goal."""
        return self.count(Status.REACHED_GOAL)

    @property
    def collided(self) -> np.ndarray:
        """``(n,)`` robots that collided: deactivated by a collision, or, under
        ``on_collision = "stall"``, stalled against a wall or a robot at least once
        (whatever they did next: one may still reach its goal)."""
        collided = self.final_status == Status.COLLIDED
        return collided if self.ever_stalled is None else collided | self.ever_stalled

    @property
    def collisions(self) -> int:
        """Robots that collided (``collided``), each counted once."""
        return int(np.count_nonzero(self.collided))

    def summary(self) -> dict[str, Any]:
        """A JSON-ready dict of the outcome."""
        collided = self.collided
        reached = self.final_status == Status.REACHED_GOAL
        times = self.goal_time[reached]
        efficiency = self.start_goal_distance[reached] / np.maximum(self.path_length[reached],
                                                                    1e-12)
        return {
            "status": self.status,
            "scenario": self.scenario,
            "algorithm": self.algorithm,
            "seed": self.seed,
            "parameters": self.parameters,
            "robots": self.robots,
            "sim_time": round(self.sim_time, 9),
            "wall_time": self.wall_time,
            "compile_time": self.compile_time,
            "steps": self.steps,
            "sim_speed": self.sim_time / self.wall_time if self.wall_time > 0 else None,
            "reached_goal": self.reached_goal,
            "collisions": self.collisions,
            "robot_collisions": int(np.sum(collided & (self.collided_with >= 0))),
            "wall_collisions": int(np.sum(collided & (self.collided_with == -1))),
            "escaped": self.count(Status.ESCAPED),
            "removed": self.count(Status.REMOVED),
            "deadlocks": int(self.ever_deadlocked.sum()),
            "livelocks": int(self.ever_livelocked.sum()),
            "exceptions": sum(1 for e in self.events if e.kind == "exception"),
            "active_at_end": self.count(Status.ACTIVE),
            # robots a collision deactivated: with reached_goal, escaped... a partition of
            # the robots, which collisions is not under "stall" (a stalled robot drives on)
            "collided_at_end": self.count(Status.COLLIDED),
            "error": self.error,
            "user_code_time": self.user_timing,
            "time_to_goal": _stats(times),
            "path_length": _stats(self.path_length),
            "path_efficiency": _stats(efficiency),
            "arrivals": self.arrivals(),
            "trajectory_digest": self.trajectory_digest,
        }

    def arrivals(self) -> dict[str, Any]:
        """Time to goal as time to an event: every robot with a goal counts.

        ``restricted_mean`` is the mean over the goal robots of their arrival time,
        each robot that never arrived (deactivated, deadlocked, still driving)
        counted at the horizon, the run's time limit: defined for every run with a
        goal robot, and never rewarding robots that fail to arrive. Robots removed
        by an edit are left out.
        """
        removed = self.final_status == Status.REMOVED
        with_goal = (np.ones(self.robots, dtype=bool) if self.has_goal is None
                     else np.asarray(self.has_goal, dtype=bool)) & ~removed
        reached = (self.final_status == Status.REACHED_GOAL) & with_goal
        times = np.sort(self.goal_time[reached])
        horizon = float(self.time_limit)
        goal_robots = int(with_goal.sum())
        restricted = None
        if goal_robots and np.isfinite(horizon):
            total = float(np.minimum(times, horizon).sum()) + horizon * (goal_robots - len(times))
            restricted = total / goal_robots
        return {"goal_robots": goal_robots, "arrived": len(times),
                "horizon": horizon if np.isfinite(horizon) else None,
                "times": [float(t) for t in times], "restricted_mean": restricted}

    def events_as_dicts(self) -> list[dict[str, Any]]:
        """Events as plain dicts."""
        return [asdict(e) for e in self.events]


def _stats(values: np.ndarray) -> dict[str, float | None]:
    if values.size == 0:
        return {"mean": None, "min": None, "max": None}
    return {"mean": float(values.mean()), "min": float(values.min()),
            "max": float(values.max())}


def result_from_state(state: WorldState, **fields_: Any) -> RunResult:
    """Collect the final per-robot arrays of a run into a :class:`RunResult`."""
    return RunResult(final_status=state.status.copy(), collided_with=state.collided_with.copy(),
                     goal_time=state.goal_time.copy(), path_length=state.path_length.copy(),
                     **fields_)


def run_digest(pose_crc: int, state: WorldState, status: str) -> str:
    """A run's digest (BLAKE2b, 32 hex digits) from the CRC-32 of every step's poses so far
    (``pose_crc``) and the robots' statuses, goal times and collisions: seeds that changed
    nothing give the same; runs that differ, another (but for a 2**-32 chance in the
    poses' CRC)."""
    digest = hashlib.blake2b(pose_crc.to_bytes(4, "little"), digest_size=16)
    for array in (state.status, state.goal_time, state.collided_with):
        digest.update(np.ascontiguousarray(array).data)
    digest.update(f"{status}:{state.step}".encode())
    return digest.hexdigest()
