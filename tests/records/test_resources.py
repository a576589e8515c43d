"""The memory a run needs is estimated before allocating, and a run too large is refused."""

from __future__ import annotations

import contextlib
import io
import tracemalloc

import numpy as np
import pytest

import mimics.records.resources as resources
from mimics.engine.simulation import Simulation
from mimics.interfaces.cli import main
from mimics.records.resources import available_memory, check_memory, run_memory
from mimics.records.runner import prepare
from mimics.scenarios.line import scenario as line
from mimics.world.errors import MimicsError


def engine_part(n: int) -> int:
    parts = run_memory(line(robots=n)).parts
    return parts["state and sensors"] + parts["stall windows"]


def test_the_estimate_covers_what_the_engine_allocates_and_not_much_more() -> None:
    # one-time costs (modules imported on first use: 142 kB at 100 robots, more than
    # the estimate's margin when this test runs first)
    Simulation(line(robots=100), lambda robot: (0.0, 0.0), time_limit=0.2).run()
    for n in (100, 400, 1600):
        scenario = line(robots=n)
        tracemalloc.start()
        try:
            sim = Simulation(scenario, lambda robot: (0.0, 0.0), time_limit=0.2)
            sim.start()  # the first sensing: scans and their temporaries
            _, peak = tracemalloc.get_traced_memory()
        finally:
            tracemalloc.stop()
        estimate = engine_part(n)
        assert peak <= estimate <= 1.5 * peak, (n, peak, estimate)


def test_the_estimate_covers_the_state_arrays_one_by_one() -> None:
    sim = Simulation(line(robots=300), lambda robot: (0.0, 0.0))
    arrays = [v for part in (vars(sim.state), vars(sim.types), vars(sim._stalls))
              for v in part.values() if isinstance(v, np.ndarray)]
    assert sum(a.nbytes for a in arrays) <= engine_part(300)


def test_the_estimate_grows_with_robots_beams_and_stall_windows() -> None:
    small, large = run_memory(line(robots=10)), run_memory(line(robots=1000))
    assert large.parts["state and sensors"] == 100 * small.parts["state and sensors"]
    longer = line(robots=10).with_settings(deadlock_window=1000.0)
    assert run_memory(longer).parts["stall windows"] > 5 * small.parts["stall windows"]


def test_the_recorder_buffer_is_the_rows_of_the_run_up_to_a_part() -> None:
    """291 bytes a row buffered: a 10-robot, 1 s run (10 steps of 0.1 s) records at most
    10 * 12 rows; a long run of many robots buffers one part (flush_rows rows)."""
    short = run_memory(line(robots=10), time=1.0).parts["recorder buffer"]
    assert short == 291 * (10 * 12 + 10)
    assert run_memory(line(robots=10), time=1.0, every=5).parts["recorder buffer"] == 291 * (
        10 * 4 + 10)
    long = run_memory(line(robots=10_000), time=600.0).parts["recorder buffer"]
    assert long == 291 * (1_048_576 + 10_000)
    assert run_memory(line(robots=10_000), time=600.0, flush_rows=1000).parts[
        "recorder buffer"] == 291 * (1000 + 10_000)


def test_a_run_too_large_is_refused_in_one_line_with_the_figure_and_what_to_change() -> None:
    with pytest.raises(MimicsError) as info:
        check_memory(line(robots=100_000), available=200 * 2**20)
    message = str(info.value)
    assert "needs about" in message and "more than the 200.0 MB available" in message
    assert "fewer robots or fewer beams" in message and "\n" not in message
    windows = line(robots=1000).with_settings(deadlock_window=5000.0, livelock_window=5000.0)
    with pytest.raises(MimicsError, match=r"shorter settings\.deadlock_window"):
        check_memory(windows, available=400 * 2**20)
    assert check_memory(line(robots=10), available=2**40).total > 0


def test_the_machine_reports_its_memory() -> None:
    available = available_memory()
    assert available is None or available > 0


def test_prepare_and_the_command_line_refuse_before_allocating(
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(resources, "available_memory", lambda: 256 * 2**20)
    with pytest.raises(MimicsError, match="needs about"):
        prepare("line", "go_to_goal", robots=2000)
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        status = main(["run", "line", "go_to_goal", "--robots", "2000"])
    assert status == 2
    assert err.getvalue().startswith("mimics: error: scenario 'line': this run needs about")


@pytest.mark.parametrize(("count", "shown"), [
    (3 * 2**10, "3.0 kB"), (int(1.5 * 2**20), "1.5 MB"), (7 * 2**40, "7.0 TB"),
    (999_999 * 2**40, "999999.0 TB"), (2 * 10**6 * 2**40, "2e+06 TB"),
    (10**300, "9.09e+287 TB"),  # what deadlock_window = 1e300 once printed as 288 digits
])
def test_sizes_are_written_short_however_large(count: int, shown: str) -> None:
    assert resources.size_text(count) == shown
