"""SimulationStepper.edit: edits go through the stepper's thread, between two steps.

Paused, an edit applies at once and a frame shows it; several threads editing at
once each get their own edit back, all applied; a refusal or a malformed edit is
raised in the caller's thread, one line; after the end nothing is edited.
"""

from __future__ import annotations

import math
import threading

import pytest

from mimics.interfaces.stepper import SimulationStepper
from mimics.records.runner import prepare
from mimics.world.edits import EditError
from mimics.world.errors import MimicsError


def paused_stepper(frames: list[tuple[int, int]]) -> SimulationStepper:
    sim = prepare("line", "go_to_goal", robots=6, time=3.0, seed=2)
    stepper = SimulationStepper(sim, lambda s: frames.append((s.state.step, len(s.world_map
                                                                                .segments))),
                                speed=math.inf)
    for _ in range(3):
        stepper.step()
    assert stepper.wait_paused()
    return stepper


def test_a_paused_edit_applies_at_once_and_is_drawn():
    frames: list[tuple[int, int]] = []
    stepper = paused_stepper(frames)
    try:
        applied = stepper.edit({"kind": "add_wall", "segment": [10.0, -4.0, 10.0, -3.0]})
        assert applied == {"step": 3, "kind": "add_wall", "segment": [10.0, -4.0, 10.0, -3.0],
                           "time": 0.3, "detail": "add wall segment [10, -4, 10, -3]"}
        assert stepper.sim.state.step == 3 and stepper.state == "paused"
        assert frames[-1] == (3, 1)  # a frame of step 3 with the new wall
    finally:
        stepper.close()


def test_edits_from_several_threads_are_all_applied_each_returned_to_its_caller():
    stepper = paused_stepper([])
    results: dict[int, dict] = {}

    def move(robot: int) -> None:
        results[robot] = stepper.edit({"kind": "set_goal", "robot": robot, "x": 15.0,
                                       "y": float(robot)})

    threads = [threading.Thread(target=move, args=(robot,)) for robot in range(6)]
    try:
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(60)
        assert sorted(results) == list(range(6))
        assert all(results[r]["robot"] == r and results[r]["y"] == r for r in range(6))
        assert stepper.sim.state.goal[:, 1].tolist() == [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]
        assert len(stepper.sim.scenario.edits) == 6
    finally:
        stepper.close()


def test_refusals_and_malformed_edits_are_raised_in_the_callers_thread():
    stepper = paused_stepper([])
    try:
        with pytest.raises(EditError, match=r"^edit.x: expected a number, got 'abc'$"):
            stepper.edit({"kind": "set_goal", "robot": 0, "x": "abc", "y": 1.0})
        with pytest.raises(EditError, match=r"outside the map bounds"):
            stepper.edit({"kind": "move_robot", "robot": 0, "x": 1e6, "y": 0.0})
        assert stepper.sim.scenario.edits == ()
        stepper.step()  # the thread goes on after a refusal
        assert stepper.wait_paused() and stepper.sim.state.step == 4
    finally:
        stepper.close()


def test_nothing_is_edited_after_the_end():
    stepper = paused_stepper([])
    stepper.play()
    assert stepper.wait_ended(timeout=120)
    with pytest.raises(MimicsError, match="the run has ended"):
        stepper.edit({"kind": "remove_robot", "robot": 0})
