"""A robot's own scan read traces its row while helper threads trace the others; every
row read is the one a whole trace gives, bit for bit, and no trace outlives its step."""

from __future__ import annotations

import numpy as np
import pytest

import mimics.engine.helper_threads.threads as kernel_threads
import mimics.engine.ranging.ranger as ranger_module
import mimics.engine.ranging.scanner as scanner_module
from mimics.catalog import load_scenario
from mimics.engine.simulation import Simulation
from tests.threads import thread_count


class RowRecorder:
    """Keeps a copy of each robot's ranges and hits as it read them (``readers``: the
    robots that read their scan at all), and turns on the spot: the scans change at
    every step, and the robots read them faster than a helper traces them."""

    def __init__(self, readers: set[int] | None = None) -> None:
        self.readers = readers
        self.rows: dict[tuple[int, int], tuple[bytes, bytes]] = {}

    def step(self, robot):
        if self.readers is not None and robot.id not in self.readers:
            return 0.0, robot.heading
        self.rows[(round(robot.time / robot.dt), robot.id)] = (robot.scan.ranges.tobytes(),
                                                        robot.scan.hits.tobytes())
        return 0.0, robot.heading + 0.3


def recorded_run(threads: int, readers: set[int] | None = None,
                 robots: int = 60) -> tuple[RowRecorder, Simulation]:
    recorder = RowRecorder(readers)
    with thread_count(threads):
        # rows are traced on helper threads for noise-free scans only (Scanner.trace_row)
        sim = Simulation(load_scenario("obstacle_room", robots=robots, noise="off"),
                         recorder.step, seed=5, time_limit=4.0)
        sim.run()
    return recorder, sim


@pytest.fixture
def flights(monkeypatch: pytest.MonkeyPatch) -> dict[str, int]:
    """Counts the traces started on helper threads and the ends of those traces."""
    counts = {"started": 0, "finished": 0}
    start = ranger_module.start_beams

    def counted_start(*args, **kwargs):
        flight = start(*args, **kwargs)
        if flight is not None:
            counts["started"] += 1
            finish = flight.finish

            def counted_finish() -> None:
                counts["finished"] += 1
                finish()

            flight.finish = counted_finish  # type: ignore[method-assign]
        return flight

    monkeypatch.setattr(scanner_module, "start_beams", counted_start)
    return counts


def test_rows_read_by_the_robots_are_those_of_a_whole_trace(flights):
    alone, alone_sim = recorded_run(threads=1)  # one thread: whole traces, no helpers
    assert flights["started"] == 0
    shared, shared_sim = recorded_run(threads=2)
    assert flights["started"] == shared_sim.state.step  # every step's reads went by rows
    assert shared.rows.keys() == alone.rows.keys()
    assert shared.rows == alone.rows
    np.testing.assert_array_equal(shared_sim.state.pose, alone_sim.state.pose)


def test_a_row_read_waits_for_its_trace_and_the_step_ends_the_rest(flights):
    """Robot 0 reads, then at once robot 59, whose row the helper may not have traced
    yet: it waits for it. Rows between are traced meanwhile, and the step ends that
    trace (the buffers are never written while robots move)."""
    shared, sim = recorded_run(threads=2, readers={0, 59})
    assert flights["started"] == flights["finished"] == sim.state.step
    alone, alone_sim = recorded_run(threads=1, readers={0, 59})
    assert shared.rows == alone.rows
    # after the run: the last sensing's whole scan, equal with or without helpers
    np.testing.assert_array_equal(sim.state.scan, alone_sim.state.scan)
    np.testing.assert_array_equal(sim.state.scan_hit, alone_sim.state.scan_hit)


def test_where_no_row_can_be_seen_traced_a_read_finishes_the_trace(
        flights, monkeypatch: pytest.MonkeyPatch):
    """As on a machine other than x86 (``Flight.looks`` False, ``done`` always False): a
    row read not known traced finishes the whole trace, once a step, instead of a help
    call per read; the rows are still those of a whole trace."""
    helps = []
    monkeypatch.setattr(kernel_threads.Flight, "looks", False)
    monkeypatch.setattr(kernel_threads.Flight, "done", lambda self, chunk: False)
    monkeypatch.setattr(kernel_threads.Flight, "help_until",
                        lambda self, chunk: helps.append(chunk))
    shared, sim = recorded_run(threads=2)
    assert flights["started"] == flights["finished"] == sim.state.step
    assert helps == []
    alone, _ = recorded_run(threads=1)
    assert shared.rows == alone.rows


@pytest.mark.parametrize("threads", [1, 2])
def test_the_sight_lists_are_updated_once_per_sensing(monkeypatch: pytest.MonkeyPatch,
                                                      threads: int):
    """They count the steps a neighbourhood stood still: a second update in one step
    would count one step twice."""
    from mimics.engine.ranging.still_scans import StillScans

    updates: list[int] = []
    update = StillScans.update

    def counted(self, centers, walls, robots):
        updates.append(1)
        return update(self, centers, walls, robots)

    monkeypatch.setattr(StillScans, "update", counted)
    _recorder, sim = recorded_run(threads=threads)
    assert len(updates) == sim.state.step  # one sensing read per step (the last unread)
