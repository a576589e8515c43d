"""Steps that return texts or truth values: ``float("1")`` and ``float(True)`` succeed,
but such a step has a bug; it is an invalid output naming the robot, as any non-number."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import mimics

BAD = [("1", "2"), (True, 0.0), (0.5, False), (np.bool_(True), 0.0), ("0.5", 0.0),
       (b"1", 0.0), (np.array("1"), 0.0), (np.array([True]), 0.0)]
GOOD = [(0.5, 0.0), (1, 0), (np.float32(0.5), np.int64(0)), (np.array(0.5), 0.0)]


@pytest.mark.parametrize("output", BAD, ids=repr)
def test_a_step_returning_texts_or_truth_values_is_an_invalid_output(output: Any) -> None:
    run = mimics.simulate("line", lambda robot: output, robots=2, time=0.3, seed=1,
                          on_error="record")
    assert run.status == "error"
    message = run.summary()["error"]
    assert "InvalidOutput" in message and "robot 0" in message and "two numbers" in message


@pytest.mark.parametrize("output", GOOD, ids=repr)
def test_numbers_of_every_usual_type_still_drive(output: Any) -> None:
    run = mimics.simulate("line", lambda robot: output, robots=2, time=0.3, seed=1)
    assert run.status == "time_limit"


@pytest.mark.parametrize("speeds", [["1", "1"], [True, False], np.array(["1", "1"])], ids=repr)
def test_a_team_step_returning_texts_or_truth_values_is_an_invalid_output(speeds: Any) -> None:
    class Team:
        @staticmethod
        def team_step(team: Any) -> Any:
            return speeds, np.zeros(2)

    run = mimics.simulate("line", Team, robots=2, time=0.3, seed=1, on_error="record")
    assert run.status == "error"
    assert "team_step() must return" in run.summary()["error"]
