"""A kernel compiled during a run is counted on the compile clock, not in the run's own
wall time or its user code's time (``mimics.engine.compiling.compile_clock``)."""

import threading
import time

import numpy as np
import pytest
from numba import njit

from mimics.catalog import load_scenario
from mimics.engine.compiling import compile_seconds, waiting
from mimics.engine.simulation import Simulation


def compiled_in_the_first_call(team: bool):  # type: ignore[no-untyped-def]
    """An algorithm whose first call compiles a kernel of its own (not cached)."""

    @njit(cache=False)
    def fresh(x: float) -> float:
        total = 0.0
        for k in range(5):
            total += np.sin(x * k) ** 2
        return total

    calls: list[float] = []

    def step(robot):  # type: ignore[no-untyped-def]
        if not calls:
            calls.append(fresh(1.0))
        return 0.0, 0.0

    def team_step(team_view):  # type: ignore[no-untyped-def]
        if not calls:
            calls.append(fresh(1.0))
        return np.zeros(len(team_view.ids)), np.zeros(len(team_view.ids))

    return team_step if team else step


@pytest.mark.parametrize("team", [False, True])
def test_a_compile_in_user_code_is_not_the_runs_time(team: bool) -> None:
    sim = Simulation(load_scenario("line", robots=3), compiled_in_the_first_call(team), seed=1,
                     time_limit=0.3)
    before = compile_seconds()
    began = time.perf_counter()
    result = sim.run()
    elapsed = time.perf_counter() - began
    compiled = compile_seconds() - before
    assert compiled > 0.005  # Numba compiled the kernel during the run
    assert result.compile_time == pytest.approx(compiled)
    assert result.summary()["compile_time"] == result.compile_time
    # the run's own time is what is left of it
    assert 0.0 <= result.wall_time <= elapsed - compiled + 1e-6
    # and the user code's calls are left their own time: the compile is gone from them
    assert result.user_timing["max"] < compiled
    assert result.user_timing["mean"] * result.user_timing["calls"] < compiled


def test_waits_count_while_under_way_and_once_when_nested() -> None:
    before = compile_seconds()
    began = time.perf_counter()
    seen_elsewhere: list[float] = []
    with waiting():
        time.sleep(0.2)
        # another thread (the wall-limit watchdog) sees the wait under way
        reader = threading.Thread(target=lambda: seen_elsewhere.append(compile_seconds()))
        reader.start()
        reader.join()
        with waiting():  # nested: counted once
            time.sleep(0.1)
    elapsed = time.perf_counter() - began
    total = compile_seconds() - before
    assert seen_elsewhere[0] - before >= 0.2
    assert 0.3 <= total <= elapsed
