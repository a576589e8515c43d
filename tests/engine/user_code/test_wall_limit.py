"""A step that never returns is stopped at the wall limit: the run ends, names the robot,
the step and the line it was stuck at, keeps its records, and leaves no thread behind."""

from __future__ import annotations

import textwrap
import threading
from pathlib import Path

import numpy as np
import pytest

import mimics
from mimics.catalog import find_algorithm
from mimics.engine.simulation import Simulation
from mimics.engine.state import Status
from mimics.engine.user_code.watchdog import GRACE, IDLE, POLL, RETRY
from mimics.scenarios.line import scenario as line

LIMIT = 0.5
#: A bound that only a run the watchdog failed to stop exceeds (not a speed test).
NEVER = LIMIT + GRACE + 20 * RETRY

SPIN = """\
def step(robot):
    if robot.id == 1 and robot.time > 0.25:
        x = 0
        while True:
            x += 1
    return 0.5, 0.0
"""


def threads_left(before: set[threading.Thread]) -> set[threading.Thread]:
    """Threads started since ``before`` still alive once the watchdogs' thread has had the
    time to end by itself (it outlives a run by IDLE seconds, for the next run)."""
    for thread in set(threading.enumerate()) - before:
        thread.join(IDLE + 2 * POLL + 5.0)
    return {t for t in set(threading.enumerate()) - before if t.is_alive()}


def load(folder: Path, name: str, text: str):
    (folder / name).write_text(textwrap.dedent(text))
    return find_algorithm(str(folder / name))[1]


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_a_python_step_that_never_returns_is_stopped_where_it_loops(here: Path) -> None:
    threads = set(threading.enumerate())
    result = mimics.simulate("line", load(here, "spin.py", SPIN), robots=3, wall_limit=LIMIT,
                             out=here / "run")
    assert result.status == "wall_limit"
    first, source = result.error.split("\n")
    assert first.startswith("robot 1: step() did not return within the wall limit of 0.5 s; "
                            "stopped at step 3 (t=0.3 s), spin.py:")
    assert first.endswith((":4", ":5"))  # the loop's test or its body
    assert source in ("    while True:", "    x += 1")
    assert LIMIT <= result.wall_time < NEVER
    assert threads_left(threads) == set()  # the watchdogs' thread ended after the run
    # the records hold the run up to its last whole step, and the stopped robot's error
    run = mimics.load_run(here / "run")
    assert run.complete and run.summary["status"] == "wall_limit"
    assert run.summary["error"] == result.error and run.summary["exceptions"] == 1
    assert int(run.trajectory["step"].max()) == 3
    assert result.final_status.tolist() == [Status.ACTIVE, Status.ERROR, Status.ACTIVE]
    event = run.read_events(kinds=["exception"]).iloc[0]
    assert event["robot"] == 1 and event["detail"].startswith(
        "Exception: StepTimeout: step() did not return within the wall limit of 0.5 s (spin.py:")
    assert 'spin.py", line' in event["traceback"] and "in step" in event["traceback"]
    assert "mimics/engine" not in event["traceback"]


def test_a_step_that_swallows_the_first_interruption_is_stopped_again(here: Path) -> None:
    stubborn = load(here, "stubborn.py", """\
        def step(robot):
            try:
                while True:
                    pass
            except BaseException:
                pass
            while True:
                pass
        """)
    result = Simulation(line(robots=2), stubborn, wall_limit=LIMIT).run()
    assert result.status == "wall_limit"
    # stopped in the second loop, the first one's interruption swallowed
    assert result.error.endswith(("stubborn.py:7\n    while True:", "stubborn.py:8\n    pass"))


def test_reset_and_team_step_that_never_return_are_stopped(here: Path) -> None:
    reset = load(here, "reset.py", """\
        def reset(robot):
            while True:
                pass


        def step(robot):
            return 0.5, 0.0
        """)
    result = Simulation(line(robots=2), reset, wall_limit=LIMIT).run()
    assert result.error.startswith("robot 0: reset() did not return within the wall limit of "
                                   "0.5 s; stopped at step 0 (t=0 s), reset.py:")
    assert result.steps == 0 and result.final_status[0] == Status.ERROR
    team = load(here, "team.py", """\
        import numpy as np


        def team_step(team):
            while len(team.ids):
                np.sqrt(2.0)
            return 0.5, 0.0
        """)
    result = Simulation(line(robots=3), team, wall_limit=LIMIT).run()
    assert result.error.startswith("the team algorithm: team_step() did not return within the "
                                   "wall limit of 0.5 s; stopped at step 0 (t=0 s), team.py:")
    assert (result.final_status == Status.ERROR).all()


def test_a_limit_between_steps_ends_the_run_as_before_and_changes_nothing() -> None:
    from mimics.algorithms import go_to_goal

    threads = set(threading.enumerate())
    plain = Simulation(line(robots=4), go_to_goal, seed=3, time_limit=3.0).run()
    watched = Simulation(line(robots=4), go_to_goal, seed=3, time_limit=3.0,
                         wall_limit=3600.0).run()
    assert (watched.status, watched.error) == ("time_limit", "")
    for name in ("final_status", "path_length", "goal_time"):
        np.testing.assert_array_equal(getattr(plain, name), getattr(watched, name))
    assert threads_left(threads) == set()
