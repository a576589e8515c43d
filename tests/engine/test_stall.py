"""Deadlock and livelock detection on situations built on purpose."""

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.engine.simulation import Simulation
from mimics.engine.stall import StallDetector
from mimics.engine.state import Status, WorldState
from mimics.world.maps import Map
from mimics.world.robot_types import RobotType
from mimics.world.scenario import Scenario, Settings

BLIND = RobotType("blind", width=0.5, length=0.7, kv=1.0, kw=1.0, tau_v=0.5, tau_w=0.2)


def scen(stage, goal, walls=(), **settings) -> Scenario:
    m = Map(np.array(walls, dtype=float).reshape(-1, 4), (-20, -20, 20, 20))
    base = {"time_limit": 60.0, "deadlock_window": 5.0, "livelock_window": 15.0}
    return Scenario.from_matrix([[*stage, *goal]], m, BLIND,
                                settings=Settings(**{**base, **settings}))


def test_robot_told_to_stay_still_far_from_its_goal_is_deadlocked() -> None:
    result = Simulation(scen((0, 0, 0, 0), (10, 0)), lambda r: (0.0, 0.0)).run()
    assert result.final_status[0] == Status.DEADLOCK
    event = next(e for e in result.events if e.kind == "deadlock")
    assert event.time == 5.0 and event.start == 0.0
    assert result.summary()["deadlocks"] == 1


def test_deadlock_is_only_flagged_when_deactivation_is_off() -> None:
    result = Simulation(scen((0, 0, 0, 0), (10, 0), deactivate_on_deadlock=False),
                        lambda r: (0.0, 0.0), time_limit=8).run()
    assert result.final_status[0] == Status.ACTIVE
    assert result.summary()["deadlocks"] == 1


def test_circling_robot_is_in_livelock_not_deadlock() -> None:
    def circle(robot):
        return 0.5, robot.heading + 0.6

    result = Simulation(scen((0, 0, 0, 0), (15, 0)), circle, time_limit=40).run()
    summary = result.summary()
    assert summary["livelocks"] == 1
    assert summary["deadlocks"] == 0
    event = next(e for e in result.events if e.kind == "livelock")
    assert event.start == event.time - 15.0


def test_robot_that_waits_then_goes_is_not_flagged() -> None:
    def wait_then_go(robot):
        if robot.time < 4.0:
            return 0.0, 0.0
        gx, gy = robot.goal
        x, y, _ = robot.pose
        return 1.0, math.atan2(gy - y, gx - x)

    result = Simulation(scen((0, 0, 0, 0), (10, 0)), wait_then_go).run()
    summary = result.summary()
    assert result.final_status[0] == Status.REACHED_GOAL
    assert summary["deadlocks"] == 0 and summary["livelocks"] == 0


# -- the exact deadlock check against a brute-force window ------------------

def _brute_force_deadlock(history: list[np.ndarray], window: int, limit: float,
                          candidates: np.ndarray) -> np.ndarray:
    """Every position over the last ``window`` steps within ``limit`` of now (no shortcut)."""
    if len(history) <= window:
        return np.zeros(len(candidates), dtype=bool)
    now = history[-1]
    spread = np.zeros(len(now))
    for past in history[-(window + 1):]:
        spread = np.maximum(spread, np.hypot(*(past - now).T))
    return candidates & (spread <= limit)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), robots=st.integers(1, 6),
       window=st.integers(1, 12), limit=st.sampled_from([0.0, 0.05, 0.3]),
       still=st.floats(0.0, 0.9))
def test_deadlock_matches_a_brute_force_window_check(seed: int, robots: int, window: int,
                                                       limit: float, still: float) -> None:
    # A random walk whose robots often stand still (or barely move) for a
    # while: the shortcut of the detector must never change the verdict.
    rng = np.random.default_rng(seed)
    dt = 0.1
    settings_ = Settings(dt=dt, deadlock_window=window * dt, livelock_window=1.0,
                         deadlock_distance=limit)
    rows = np.tile([0.0, 0.0, 0.0, 0.0, 10.0, 0.0], (robots, 1))
    scenario = Scenario.from_matrix(rows, Map(np.zeros((0, 4)), (-50, -50, 50, 50)), BLIND,
                                    settings=settings_)
    state = WorldState.from_scenario(scenario, 0)
    detector = StallDetector(settings_, robots)
    assert detector.deadlock_steps == window
    history = []
    for _ in range(4 * window + 10):
        moving = rng.random(robots) > still
        sizes = rng.choice([1e-3, 0.02, 0.2, 1.0], size=robots)
        state.pose[:, :2] += moving[:, None] * rng.normal(0.0, 1.0, (robots, 2)) * sizes[:, None]
        history.append(state.pose[:, :2].copy())
        expected = _brute_force_deadlock(history, window, limit, state.active)
        detector.update(state)
        assert np.array_equal(state.in_deadlock, expected)



def _record_only(positions, distances, count, pose, distance, *_):
    """The screen's bookkeeping without its verdict: every step takes the exact path."""
    positions[count % len(positions)] = pose[:, :2]
    distances[count % len(distances)] = distance
    return False


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), robots=st.integers(1, 6), window=st.integers(1, 8),
       limit=st.sampled_from([0.0, 0.05, 0.3]), progress=st.sampled_from([0.0, 0.1, 0.5]),
       still=st.floats(0.0, 0.9))
def test_the_compiled_screen_never_changes_a_stall_verdict(
        seed: int, robots: int, window: int, limit: float, progress: float,
        still: float) -> None:
    # Two detectors on the same random walks, one screening with the compiled check and
    # one always taking the exact NumPy path: the same flags and stall state at every step,
    # with robots standing still, creeping, wandering off, without goals and deactivated.
    from mimics.engine import stall

    rng = np.random.default_rng(seed)
    dt = 0.1
    settings_ = Settings(dt=dt, deadlock_window=window * dt, livelock_window=2 * window * dt,
                         deadlock_distance=limit, livelock_progress=progress)
    rows = np.tile([0.0, 0.0, 0.0, 0.0, 10.0, 0.0], (robots, 1))
    scenario = Scenario.from_matrix(rows, Map(np.zeros((0, 4)), (-50, -50, 50, 50)), BLIND,
                                    settings=settings_)
    screened, exact = (WorldState.from_scenario(scenario, 0) for _ in range(2))
    screened.goal[0] = exact.goal[0] = np.nan  # a robot without a goal is never stalled
    quick, slow = StallDetector(settings_, robots), StallDetector(settings_, robots)
    for step in range(6 * window + 10):
        moving = rng.random(robots) > still
        sizes = rng.choice([1e-3, 0.02, 0.2, 1.0], size=robots)
        moves = moving[:, None] * rng.normal(0.0, 1.0, (robots, 2)) * sizes[:, None]
        if step == 3 * window:  # one robot leaves the team
            screened.status[robots - 1] = exact.status[robots - 1] = Status.REACHED_GOAL
        for state in (screened, exact):
            state.pose[:, :2] += moves
        got = quick.update(screened)
        screen, stall._record_and_screen = stall._record_and_screen, _record_only
        try:
            expected = slow.update(exact)
        finally:
            stall._record_and_screen = screen
        for flag, want in zip(got, expected, strict=True):
            assert np.array_equal(flag, want)
        assert np.array_equal(screened.in_deadlock, exact.in_deadlock)
        assert np.array_equal(screened.in_livelock, exact.in_livelock)
