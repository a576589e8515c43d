"""Errors of compiled steps name the robot (or the team), the step and the code returned;
their recorded traceback holds none of mimics' frames."""

from __future__ import annotations

import mimics
from tests.native.conftest import ALGORITHMS


def test_a_team_error_names_the_step_and_the_code() -> None:
    result = mimics.simulate("line", str(ALGORITHMS / "team_fails.c"), robots=3,
                             on_error="record")
    assert result.error == ("NativeError in the team algorithm at t=0.2 s: mimics_team_step "
                            "returned 7 at step 2")
    event = next(e for e in result.result.events if e.kind == "exception")
    assert event.traceback == "mimics.native.adapter.NativeError: mimics_team_step returned 7 at " \
                              "step 2\n"
