"""Small worlds and algorithms for the records tests: each run takes well under a second."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from mimics.engine.outcome import RunResult
from mimics.engine.simulation import Simulation
from mimics.records.runner import run_to_folder
from mimics.world.maps import Map
from mimics.world.robot_types import RobotType
from mimics.world.scenario import Scenario, Settings

PROBE = RobotType("probe", width=0.4, length=0.5, kv=1.0, kw=1.0, tau_v=0.1, tau_w=0.1)
SMALL = RobotType("small", width=0.2, length=0.25, kv=0.5, kw=1.0, tau_v=0.1, tau_w=0.1)


def box_scenario(rows: list[list[float]], walls: bool = True, **settings: Any) -> Scenario:
    """Robots ``[x, y, yaw, v(, gx, gy)]`` in a 10 x 10 m box (or an empty 10 x 10 field)."""
    world = Map.box(10.0, 10.0) if walls else Map.empty((0.0, 0.0, 10.0, 10.0))
    base = {"dt": 0.1, "time_limit": 8.0, "deadlock_window": 1.0, "livelock_window": 2.0}
    return Scenario.from_matrix(rows, world, PROBE, settings=Settings(**{**base, **settings}),
                                name="box")


def head_on() -> Scenario:
    """Robots 0 and 1 drive into each other, 2 into the east wall, 3 reaches its goal."""
    return box_scenario([[2, 5, 0, 0, 8.5, 5], [8, 5, np.pi, 0, 1.5, 5], [5, 2, 0, 0, 12, 2],
                         [5, 8, np.pi / 2, 0, 5, 9.0]])


def record(scenario: Scenario, algorithm: Any, folder: Path, seed: int = 1,
           policy: str = "abort", **options: Any) -> RunResult:
    """Run and record into ``folder``."""
    sim = Simulation(scenario, algorithm, seed=seed, policy=policy)  # type: ignore[arg-type]
    return run_to_folder(sim, folder, **options)


def stay(robot: Any) -> tuple[float, float]:
    """Never move: a deadlock once the window has passed."""
    return 0.0, robot.heading


def circle(robot: Any) -> tuple[float, float]:
    """Drive in circles, logging a message with a separator in it: a livelock."""
    robot.log("going; round")
    return 0.5, robot.heading + 1.0


def fail_robot_1(robot: Any) -> tuple[float, float]:
    """Robot 1 divides by zero at t = 0.5 s; the others creep forward."""
    if robot.id == 1 and robot.time > 0.45:
        return 1 / 0, 0.0
    return 0.2, robot.heading


class ScanCapture:
    """An observer keeping, at every step, the engine's scans of the robots then active."""

    def __init__(self) -> None:
        self.seen: dict[tuple[int, int], tuple[np.ndarray, np.ndarray]] = {}

    def on_start(self, sim: Simulation) -> None:
        self.on_step(sim)

    def on_step(self, sim: Simulation) -> None:
        state = sim.state
        for robot in np.flatnonzero(state.active):
            beams = sim.scenario.robot_type(int(robot)).ranger.beams
            if beams:
                self.seen[(state.step, int(robot))] = (state.scan[robot, :beams].copy(),
                                                      state.scan_hit[robot, :beams].copy())
