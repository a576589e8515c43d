"""The ranger's rays are cast when its scan is first read, from the state of the sensing.

A run whose algorithm and observers read no scan casts no ray; reading or not
reading changes no result, noisy sensors included; and whatever is read (by a
per-robot or team algorithm, an observer, or after the run) equals the scan
traced directly, with the ray kernel, from the pose the robots had when sensed.
"""

from dataclasses import replace

import numpy as np
import pytest

import mimics.engine.ranging.scanner as scanner_module
from mimics.algorithms import go_to_goal
from mimics.engine.ranging.ranger import RangerQuery, trace_beams
from mimics.engine.simulation import Simulation
from mimics.scenarios.line import scenario as line
from mimics.world.robot_types import PositioningNoise
from mimics.world.scenario import Scenario


@pytest.fixture
def traces(monkeypatch) -> list[int]:
    """Counts the scanner's calls of the ray kernel's entry point (one per scan)."""
    calls: list[int] = []

    def counted(*args, **kwargs):
        calls.append(1)
        return trace_beams(*args, **kwargs)

    monkeypatch.setattr(scanner_module, "trace_beams", counted)
    return calls


def noisy_line(robots: int = 4) -> Scenario:
    """The line, with a noisy ranger and noisy positioning (both draw random numbers)."""
    scenario = line(robots=robots)
    kind = scenario.types[0]
    noisy = replace(kind, ranger=replace(kind.ranger, sigma=0.05),
                    positioning=PositioningNoise(sigma_position=0.02))
    return replace(scenario, types=(noisy,))


class ScanReader:
    """An observer that keeps a copy of the scan after the steps it is asked to read."""

    def __init__(self, steps: set[int] | None = None) -> None:
        self.steps = steps  # None: every step
        self.scans: dict[int, np.ndarray] = {}

    def on_step(self, sim: Simulation) -> None:
        step = sim.state.step
        if self.steps is None or step in self.steps:
            self.scans[step] = sim.state.scan.copy()


def direct_scan(sim: Simulation) -> np.ndarray:
    """The noise-free scan of the present pose, traced here with the ray kernel."""
    state, types = sim.state, sim.types
    query = RangerQuery(np.ascontiguousarray(state.pose[:, :2]),
                        np.ascontiguousarray(state.pose[:, 2]), types.beam_offsets,
                        types.max_range, np.arange(state.n), types.beam_units, types.beam_fans)
    return trace_beams(query, sim.walls, sim._robot_index())[0]


def test_a_run_that_reads_no_scan_casts_no_ray(traces) -> None:
    sim = Simulation(line(robots=3), go_to_goal, seed=1, time_limit=2.0)
    result = sim.run()
    assert result.reached_goal == 0 and sim.state.step == 20
    assert traces == []


def test_each_sensing_read_is_traced_once(traces) -> None:
    reader = ScanReader()
    sim = Simulation(line(robots=3), go_to_goal, seed=1, time_limit=2.0, observers=[reader])
    sim.run()
    assert np.array_equal(sim.state.scan, reader.scans[20], equal_nan=True)  # read already
    assert len(traces) == 20 == len(reader.scans)


def test_reading_the_scan_changes_no_result() -> None:
    def run(observers):
        sim = Simulation(noisy_line(), go_to_goal, seed=3, time_limit=4.0, observers=observers)
        sim.run()
        return sim.state

    unread, read = run([]), run([ScanReader()])
    for name in ("pose", "measured_pose", "velocity", "odometry", "status"):
        assert np.array_equal(getattr(unread, name), getattr(read, name)), name


def test_noise_of_a_scan_does_not_depend_on_earlier_reads() -> None:
    every, once = ScanReader(), ScanReader({25})
    for reader in (every, once):
        Simulation(noisy_line(), go_to_goal, seed=5, time_limit=3.0, observers=[reader]).run()
    assert np.array_equal(every.scans[25], once.scans[25])
    assert not np.array_equal(every.scans[25], every.scans[24])  # the robots moved


def test_what_is_read_is_the_scan_of_the_sensed_pose() -> None:
    seen: dict[int, np.ndarray] = {}
    traced: dict[int, np.ndarray] = {}

    def team_step(team):  # a team algorithm that reads the scan at odd steps only
        step = round(team.time / team.dt)
        if step % 2:
            seen[step] = team.scan.ranges.copy()
        heading = np.arctan2(team.goal[:, 1] - team.pose[:, 1], team.goal[:, 0] - team.pose[:, 0])
        return np.full(len(team), 0.5), heading

    class Tracer:
        def on_step(self, sim: Simulation) -> None:
            traced[sim.state.step] = direct_scan(sim)

    exact = line(robots=3).with_settings(noise="off")  # direct_scan traces without noise
    sim = Simulation(exact, team_step, seed=1, time_limit=2.0, observers=[Tracer()])
    sim.run()
    assert sorted(seen) == list(range(1, 20, 2))
    for step, scan in seen.items():
        assert np.array_equal(scan, traced[step], equal_nan=True)
    assert np.array_equal(sim.state.scan, direct_scan(sim), equal_nan=True)  # after the end
