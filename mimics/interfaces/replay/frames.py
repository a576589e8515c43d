"""A run's trajectory as dense arrays over (recorded step, robot), and the frame times.

The run's ``trajectory.parquet`` (one row per robot per recorded step) is
turned into dense arrays; a robot missing from later rows keeps its last pose
and state. A frame at simulated time ``t`` shows the last recorded step at or
before ``t``, exactly as logged (no interpolation).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from mimics.engine.state import Status
from mimics.interfaces.replay.edits import (
    Timeline,
    applied_edits,
    break_at_moves,
    goal_timeline,
    robot_moves,
    wall_timeline,
)
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario

VIDEO_SUFFIXES = (".mp4", ".mkv", ".mov", ".avi")
_EPS = 1e-9
_TRAJECTORY_COLUMNS = ("time", "step", "robot", "x", "y", "theta", "status")
#: What the inspector shows of one robot besides its pose: speed, turn rate, references.
MOTION_COLUMNS = ("v", "w", "v_ref", "heading_ref")
_STOP_KINDS = {"reached_goal": Status.REACHED_GOAL, "collision": Status.COLLIDED,
               "escaped": Status.ESCAPED, "exception": Status.ERROR}


MAX_FRAMES = 1_000_000  # frames of one replay (a day of video at 10 fps)


def frame_times(duration: float, fps: float, speed: float) -> np.ndarray:
    """Simulated times of the frames: every ``speed / fps`` s from 0, plus the end."""
    if not fps > 0 or not speed > 0:
        raise MimicsError(f"replay: fps and speed must be positive, got fps={fps}, "
                          f"speed={speed}")
    step = speed / fps
    frames = duration / step
    if not frames <= MAX_FRAMES:  # also NaN and inf
        raise MimicsError(f"replay: {duration:g} s at {speed:g} simulated s per s and {fps:g} "
                          f"fps is {frames:.3g} frames, over the limit of {MAX_FRAMES} (expected "
                          "a higher speed or fewer fps)")
    count = math.floor(frames + _EPS) + 1
    times = np.arange(count) * step
    if duration - times[-1] > _EPS:
        times = np.append(times, duration)
    return np.round(times, 9)


def open_run(run: str | Path | Any) -> Any:
    """A loaded run: a folder path goes through ``mimics.load_run``; objects pass through.

    Raises:
        MimicsError: when the folder is not a run or its files are unreadable.
    """
    if not isinstance(run, str | Path):
        return run
    path = Path(run)
    if not path.is_dir():
        raise MimicsError(f"{path}: not a run folder (no such directory)")
    from mimics.records.run_folder import load_run

    return load_run(path)


@dataclass
class ReplayData:
    """A run's trajectory as dense arrays, ready to draw at any time.

    Attributes:
        times: ``(T,)`` simulated times of the recorded steps, increasing.
        pose: ``(T, n, 3)`` true x, y, theta (float32).
        status: ``(T, n)`` ``Status`` codes.
        livelock: ``(T, n)`` active robots in a livelock (from the events).
        scenario: the run's scenario (map, robot types, goals).
        title: scenario / algorithm / seed.
        steps: ``(T,)`` the step number of each recorded step.
        walls: the run's wall sets over its steps (one set for a run without wall edits).
        moves: robot -> the steps at which an edit moved it (its trail breaks there).
        goals: the run's goals over its steps (``set_goal`` edits).
    """

    times: np.ndarray
    pose: np.ndarray
    status: np.ndarray
    livelock: np.ndarray
    scenario: Scenario
    title: str
    steps: np.ndarray | None = None
    walls: Timeline | None = None
    moves: dict[int, np.ndarray] | None = None
    goals: Timeline | None = None

    def __post_init__(self) -> None:
        if self.steps is None:
            self.steps = np.arange(len(self.times), dtype=np.int64)
        if self.walls is None:
            self.walls = wall_timeline(self.scenario.map.segments, ())
        if self.moves is None:
            self.moves = {}
        if self.goals is None:
            self.goals = goal_timeline(self.scenario.goals, ())
        #: ``(T,)`` the index of the wall set shown at each recorded step.
        self.wall_set: np.ndarray = self.walls.set_at(self.steps)

    def goals_at(self, k: int) -> np.ndarray:
        """The goals ``(n, 2)`` at recorded step ``k`` (NaN rows: no goal)."""
        assert self.goals is not None and self.steps is not None
        return self.goals.sets[int(self.goals.set_at(self.steps[k]))]

    def walls_at(self, k: int) -> np.ndarray:
        """The walls ``(m, 4)`` at recorded step ``k``."""
        assert self.walls is not None
        return self.walls.sets[int(self.wall_set[k])]

    @property
    def n(self) -> int:
        """Number of robots."""
        return int(self.pose.shape[1])

    @property
    def duration(self) -> float:
        """Simulated time of the last recorded step (s)."""
        return float(self.times[-1])

    @property
    def half_sizes(self) -> tuple[np.ndarray, np.ndarray]:
        """Half length and half width of every robot."""
        s = self.scenario
        lengths = np.array([t.length for t in s.types])[s.type_index]
        widths = np.array([t.width for t in s.types])[s.type_index]
        return lengths / 2, widths / 2

    def index_at(self, t: float) -> int:
        """Index of the last recorded step at or before ``t`` (clamped to the run)."""
        k = int(np.searchsorted(self.times, t + _EPS, side="right")) - 1
        return min(max(k, 0), len(self.times) - 1)

    def trails(self, k: int, seconds: float, points: int) -> np.ndarray | None:
        """Recent positions ``(n, m, 2)`` up to step ``k`` over ``seconds``, at most
        ``points`` + 1 of them per robot."""
        if seconds <= 0:
            return None
        first = int(np.searchsorted(self.times, self.times[k] - seconds - _EPS))
        if k - first < 1:
            return None
        idx = np.unique(np.linspace(first, k, min(points + 1, k - first + 1)).round().astype(int))
        trails = self.pose[idx, :, :2].transpose(1, 0, 2)
        if not self.moves:
            return trails
        assert self.steps is not None
        steps = self.steps[idx]
        trails = trails.astype(np.float64)
        for robot, moved_at in self.moves.items():
            broken = break_at_moves(trails[robot], steps, moved_at)
            if len(broken) > len(steps):  # a gap at each jump; the oldest points make room
                trails[robot] = broken[len(broken) - len(steps):]
        return trails


def replay_data(run: Any) -> ReplayData:
    """Dense arrays from a loaded run (``summary``, ``trajectory``, ``events``, ``scenario``).

    Raises:
        MimicsError: when the trajectory lacks columns or names unknown robots.
    """
    scenario: Scenario = run.scenario
    n = scenario.robot_count
    traj = _trajectory(run, list(_TRAJECTORY_COLUMNS), _TRAJECTORY_COLUMNS)
    if len(traj) == 0:
        raise MimicsError("the run's trajectory is empty: nothing to replay")
    steps = traj["step"].to_numpy(np.int64)
    robot = traj["robot"].to_numpy(np.int64)
    if robot.min() < 0 or robot.max() >= n:
        raise MimicsError(f"the run's trajectory names robot {int(robot.max())}, but its "
                          f"scenario has robots 0..{n - 1}")
    recorded, row_step = np.unique(steps, return_inverse=True)
    times = np.zeros(len(recorded))
    times[row_step] = traj["time"].to_numpy(np.float64)
    xyz = traj[["x", "y", "theta"]].to_numpy(np.float32)
    # Row 0 is the scenario's initial state, used until a robot's first record.
    steps_n = len(recorded) + 1
    pose = np.empty((steps_n, n, 3), dtype=np.float32)
    pose[0] = scenario.stages[:, :3]
    status = np.zeros((steps_n, n), dtype=np.int8)
    have = np.zeros((steps_n, n), dtype=bool)
    have[0] = True
    pose[row_step + 1, robot] = xyz
    status[row_step + 1, robot] = traj["status"].to_numpy(np.int8)
    have[row_step + 1, robot] = True
    source = np.where(have, np.arange(steps_n)[:, None], 0)
    np.maximum.accumulate(source, axis=0, out=source)
    cols = np.arange(n)[None, :]
    pose, status = pose[source, cols][1:], status[source, cols][1:]
    last_row = source[-1]
    _apply_stops(status, times, last_row - 1, _events(run))
    livelock = _livelock_mask(times, n, _events(run))
    summary = getattr(run, "summary", {}) or {}
    title = " / ".join(str(summary[k]) for k in ("scenario", "algorithm") if k in summary)
    if "seed" in summary:
        title += f" / seed {summary['seed']}"
    edits = applied_edits(scenario.edits, _events(run))
    return ReplayData(times, pose, status, livelock, scenario, title or scenario.name,
                      steps=recorded, walls=wall_timeline(scenario.map.segments, edits),
                      moves=robot_moves(edits), goals=goal_timeline(scenario.goals, edits))


def robot_motion(run: Any, robot: int, times: np.ndarray) -> np.ndarray:
    """One robot's :data:`MOTION_COLUMNS` at each recorded step of ``times`` (the
    :attr:`ReplayData.times` of the same run): ``(T, 4)``, each step holding the robot's last
    row at or before it, as the replay's poses do; NaN before its first row.

    Raises:
        MimicsError: when the trajectory cannot be read or lacks the columns.
    """
    traj = _trajectory(run, ["time", *MOTION_COLUMNS], MOTION_COLUMNS, robot=int(robot))
    motion = np.full((len(times), len(MOTION_COLUMNS)), np.nan)
    if len(traj) == 0:
        return motion
    row_times = traj["time"].to_numpy(np.float64)
    at = np.clip(np.searchsorted(times, row_times - _EPS), 0, len(times) - 1)
    motion[at] = traj[list(MOTION_COLUMNS)].to_numpy(np.float64)
    have = np.zeros(len(times), dtype=bool)
    have[at] = True
    source = np.where(have, np.arange(len(times)), -1)
    np.maximum.accumulate(source, out=source)
    filled = motion[np.maximum(source, 0)]
    filled[source < 0] = np.nan
    return filled


def _events(run: Any) -> Any:
    events = getattr(run, "events", None)
    if events is None or len(events) == 0 or "kind" not in events.columns:
        return None
    return events


def _apply_stops(status: np.ndarray, times: np.ndarray, last: np.ndarray, events: Any) -> None:
    """A robot whose rows stop while it looked active takes the state its events give."""
    if events is None:
        return
    stops = events[events["kind"].isin(list(_STOP_KINDS))]
    for t, r, kind in zip(stops["time"], stops["robot"], stops["kind"], strict=True):
        r = int(r)
        if not 0 <= r < status.shape[1]:
            continue
        after = max(int(last[r]) + 1, int(np.searchsorted(times, float(t) - _EPS)))
        tail = status[after:, r]
        tail[tail == Status.ACTIVE] = _STOP_KINDS[kind]


def _livelock_mask(times: np.ndarray, n: int, events: Any) -> np.ndarray:
    """Per recorded step, the robots between a ``livelock`` event and its end."""
    mask = np.zeros((len(times), n), dtype=bool)
    if events is None:
        return mask
    rows = events[events["kind"].isin(["livelock", "livelock_end"])].sort_values("time")
    open_since: dict[int, float] = {}
    for t, r, kind in zip(rows["time"], rows["robot"], rows["kind"], strict=True):
        r = int(r)
        if not 0 <= r < n:
            continue
        if kind == "livelock":
            open_since[r] = float(t)
        elif r in open_since:
            start = open_since.pop(r)
            mask[(times >= start - _EPS) & (times < float(t) - _EPS), r] = True
    for r, start in open_since.items():
        mask[times >= start - _EPS, r] = True
    return mask


def _trajectory(run: Any, columns: list[str], required: Sequence[str],
                robot: int | None = None) -> Any:
    """The run's trajectory rows (of ``robot`` only, if given) with ``columns``: a
    :class:`~mimics.records.run_folder.Run` reads only those; an in-memory run is filtered.

    Raises:
        MimicsError: when the file cannot be read or lacks one of ``required``.
    """
    reader = getattr(run, "read_trajectory", None)
    try:
        if callable(reader):
            traj = reader(columns=columns, **({} if robot is None else {"robots": [robot]}))
        else:
            traj = run.trajectory
            if robot is not None:
                traj = traj[traj["robot"] == robot]
    except MimicsError:
        raise
    except Exception as exc:  # a truncated or corrupt file, whatever the reader raised
        raise MimicsError(f"the run's trajectory cannot be read: {exc}") from exc
    missing = [c for c in required if c not in traj.columns]
    if missing:
        raise MimicsError(f"the run's trajectory lacks the column(s) {', '.join(missing)}")
    return traj
