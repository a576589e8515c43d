"""The C and C++ ports give the Python algorithms' trajectories, same scenario and seed."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

import mimics.algorithms.deployment
from mimics.records.runner import prepare
from tests.native.conftest import ALGORITHMS, EXAMPLES
from tests.stage import stage_file


def trajectory(scenario: str, algorithm: Any, seconds: float, seed: int,
               **params: Any) -> tuple[np.ndarray, Any]:
    """True poses at every step ``(steps + 1, robots, 3)`` and the run's result."""
    sim = prepare(scenario, algorithm, time=seconds, seed=seed, params=params)
    sim.start()
    poses = [sim.state.pose.copy()]
    while sim.step():
        poses.append(sim.state.pose.copy())
    return np.array(poses), sim.result()


_PYTHON: dict[str, tuple[np.ndarray, Any]] = {}


def python_trajectory(scenario: str, algorithm: str, **params: Any) -> tuple[np.ndarray, Any]:
    """A built-in algorithm's trajectory for the go-to-goal tests (worked out once each)."""
    key = f"{scenario}/{algorithm}"
    if key not in _PYTHON:
        _PYTHON[key] = trajectory(scenario, algorithm, 25.0, 4, **params)
    return _PYTHON[key]


@pytest.mark.parametrize(("port", "scenario", "params"), [
    (EXAMPLES / "c" / "go_to_goal.c", "line", {"robots": 10}),
    (EXAMPLES / "c" / "go_to_goal.c", "circle_swap", {}),  # headings of every kind
    (EXAMPLES / "cpp" / "go_to_goal.cpp", "circle_swap", {}),
    (ALGORITHMS / "go_to_goal_team.c", "circle_swap", {}),  # the team entry point
])
def test_go_to_goal_ports_follow_the_python_trajectories(port: Path, scenario: str,
                                                         params: dict[str, Any]) -> None:
    python, expected = python_trajectory(scenario, "go_to_goal", **params)
    native, result = trajectory(scenario, str(port), 25.0, 4, **params)
    assert native.shape == python.shape
    assert np.max(np.abs(native - python)) <= 1e-9
    assert (result.status, result.reached_goal, result.collisions) == (
        expected.status, expected.reached_goal, expected.collisions)
    assert result.algorithm == port.name
    assert np.max(np.abs(python[-1] - python[0])) > 1.0  # they did move


class _LibmArctan2:
    """NumPy with ``arctan2`` replaced by the C library's ``atan2`` (``math.atan2``)."""

    def __getattr__(self, name: str) -> Any:
        return getattr(np, name)

    arctan2 = staticmethod(math.atan2)


def test_deployment_port_follows_the_python_trajectories(
        monkeypatch: pytest.MonkeyPatch) -> None:
    stage_file("cave_filled.png")
    native, result = trajectory("cave", str(EXAMPLES / "c" / "deployment.c"), 10.0, 2)
    python, expected = trajectory("cave", "deployment", 10.0, 2)
    assert np.max(np.abs(native - python)) <= 1e-9
    assert np.max(np.abs(python[-1] - python[0])) > 0.5  # they did move
    assert (result.status, result.collisions) == (expected.status, expected.collisions)
    # Bit for bit once both use the C library's atan2: NumPy's arctan2 (SIMD code on
    # AVX-512 machines) differs from it by an ulp now and then, which is all that differs.
    monkeypatch.setattr(mimics.algorithms.deployment, "np", _LibmArctan2())
    libm, _ = trajectory("cave", "deployment", 10.0, 2)
    assert np.array_equal(native, libm)


def test_the_rest_of_the_abi_memory_messages_logs_comms_and_failures() -> None:
    seen: list[list[str]] = []
    watcher = SimpleNamespace(on_step=lambda sim: seen.append(list(sim.state.user_message)))
    sim = prepare("line", str(ALGORITHMS / "chatter.c"), robots=3, time=1.0, seed=0,
                  policy="deactivate", observers=(watcher,))
    result = sim.run()
    # step 1: nothing received yet; all three robots in comms
    assert seen[0] == ["step 1 inbox 0 from -1 comms 3"] * 3
    # step 2: each robot hears the two others, the lower id first
    assert seen[1] == ["step 2 inbox 2 from 1 comms 3", "step 2 inbox 2 from 0 comms 3",
                       "step 2 inbox 2 from 0 comms 3"]
    assert seen[4][0] == "step 5 inbox 2 from 1 comms 3 | giving up"
    # robot 0 is gone from step 6: robot 1 hears robot 2 only (robot 0's last words arrive)
    assert seen[5][1] == "step 6 inbox 2 from 0 comms 2"
    assert seen[6][1] == "step 7 inbox 1 from 2 comms 2"
    exceptions = [e for e in result.events if e.kind == "exception"]
    assert [(e.robot, round(e.time, 6)) for e in exceptions] == [(0, 0.4), (2, 0.7)]
    assert exceptions[0].detail == ("Exception: NativeError: robot 0: mimics_step returned 3 "
                                    "at step 4: step 5 inbox 2 from 1 comms 3 | giving up")
    assert "InvalidOutput: robot 2: mimics_step returned a non-finite reference" in (
        exceptions[1].detail)
    assert seen[-1][1] == "step 10 inbox 0 from -1 comms 1"
    assert result.status == "time_limit"
