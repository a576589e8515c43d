"""A compiled algorithm reads the stall flag (``on_collision = "stall"``) as a Python one
does: ``robot->stalled`` and ``team->stalled[k]`` give ``robot.stalled``'s trajectory."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from mimics.records.runner import prepare
from mimics.world.maps import Map
from mimics.world.robot_types import RobotType
from mimics.world.scenario import Scenario, Settings
from tests.native.conftest import ALGORITHMS

BODY = RobotType("blind", width=0.5, length=0.7, kv=1.0, kw=1.0, tau_v=0.5, tau_w=0.2)


def wall_scene(rule: str) -> Scenario:
    """Two robots driving east at a north-south wall at x = 3 (one starts nearer)."""
    world = Map(np.array([[3.0, -5.0, 3.0, 5.0]]), (-10, -10, 10, 10))
    return Scenario.from_matrix([[0.0, 0.0, 0.0, 0.0], [1.0, 2.0, 0.0, 0.0]], world, BODY,
                                settings=Settings(noise="off", on_collision=rule))


def back_off(robot: Any) -> tuple[float, float]:
    return (-0.3 if robot.stalled else 0.6), 0.0


def run(algorithm: Any, rule: str = "stall") -> tuple[np.ndarray, np.ndarray]:
    """True poses and stall flags at every step."""
    sim = prepare(wall_scene(rule), algorithm, time=10.0, seed=2)
    sim.start()
    poses, flags = [sim.state.pose.copy()], [sim.state.stalled.copy()]
    while sim.step():
        poses.append(sim.state.pose.copy())
        flags.append(sim.state.stalled.copy())
    return np.array(poses), np.array(flags)


@pytest.mark.parametrize("port", ["back_off.c", "back_off_team.c"])
def test_a_compiled_algorithm_backs_off_when_stalled_as_python_does(port: str) -> None:
    python_poses, python_flags = run(back_off)
    native_poses, native_flags = run(str(ALGORITHMS / port))
    assert python_flags[:, 0].any() and python_flags[:, 1].any()  # both bumped the wall
    assert np.array_equal(native_flags, python_flags)
    assert np.max(np.abs(native_poses - python_poses)) <= 1e-9
    # ignoring the flag pushes on into the wall: stalled more often, on another path (so
    # the flag was read, not a constant)
    pushing_poses, pushing_flags = run(lambda robot: (0.6, 0.0))
    assert pushing_flags.sum() > python_flags.sum()
    assert np.max(np.abs(pushing_poses - python_poses)) > 1e-3


def test_the_flag_is_zero_when_collisions_deactivate() -> None:
    poses, flags = run(str(ALGORITHMS / "back_off.c"), rule="deactivate")
    assert not flags.any()
    assert poses[-1, 0, 0] < 3.0  # stopped at the wall, deactivated
