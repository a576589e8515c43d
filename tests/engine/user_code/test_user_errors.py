"""Failures of user code name the file and line in the user's code and show that line; the
recorded traceback holds the user's frames only (as pytest's short tracebacks)."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import pytest

import mimics
from mimics.catalog import find_algorithm
from mimics.engine.simulation import Simulation
from mimics.engine.user_code.failure_places import is_user_file, return_lines
from mimics.scenarios.line import scenario as line

MISSPELLED = """\
import math


def step(robot):
    x, y, theta = robot.pose
    gx, gy = robot.gaol
    return 0.5, math.atan2(gy - y, gx - x)
"""


def run_file(folder: Path, name: str, text: str, robots: int = 2, **options):
    """Write ``text`` as ``folder/name`` and run it from ``folder`` (paths shown relative)."""
    (folder / name).write_text(textwrap.dedent(text))
    _, module = find_algorithm(str(folder / name))
    return Simulation(line(robots=robots), module, time_limit=1.0, **options).run()


@pytest.fixture
def here(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)
    return tmp_path


def test_an_exception_names_file_line_and_shows_the_line(here: Path) -> None:
    result = run_file(here, "my_algo.py", MISSPELLED)
    assert result.status == "error"
    assert result.error == ("AttributeError in robot 0 at t=0 s, my_algo.py:6: 'Robot' object "
                            "has no attribute 'gaol'\n    gx, gy = robot.gaol")
    event = next(e for e in result.events if e.kind == "exception")
    assert event.detail == ("Exception: AttributeError: 'Robot' object has no attribute 'gaol' "
                            "(my_algo.py:6)")
    # the traceback: the user's frame, its line, the exception; none of mimics' frames
    assert event.traceback.startswith("Traceback (most recent call last):\n  File ")
    assert f'"{here / "my_algo.py"}", line 6, in step\n    gx, gy = robot.gaol' in event.traceback
    assert event.traceback.rstrip().endswith(
        "AttributeError: 'Robot' object has no attribute 'gaol'")
    assert "mimics" not in event.traceback.replace(str(here), "")


def test_the_place_is_the_innermost_user_line_not_a_library_frame(here: Path) -> None:
    result = run_file(here, "inverse.py", """\
        import numpy as np


        def helper(robot):
            return np.linalg.inv(np.zeros((2, 2)))


        def step(robot):
            helper(robot)
            return 0.5, 0.0
        """)
    assert result.error.startswith("LinAlgError in robot 0 at t=0 s, inverse.py:5: Singular matrix")
    assert result.error.endswith("\n    return np.linalg.inv(np.zeros((2, 2)))")
    tb = next(e for e in result.events if e.kind == "exception").traceback
    assert "line 9, in step" in tb and "line 5, in helper" in tb  # both user frames, in order
    assert tb.index("in step") < tb.index("in helper")
    assert "numpy" not in tb.replace("import numpy", "").replace("np.", "").replace(
        "numpy.linalg.LinAlgError", "")


def test_a_chained_exception_keeps_both_parts_with_user_frames(here: Path) -> None:
    result = run_file(here, "chain.py", """\
        TABLE = {}


        def step(robot):
            try:
                return TABLE[robot.id]
            except KeyError as exc:
                raise RuntimeError("no entry for this robot") from exc
        """)
    assert result.error == ("RuntimeError in robot 0 at t=0 s, chain.py:8: no entry for this "
                            "robot\n    raise RuntimeError(\"no entry for this robot\") from exc")
    tb = next(e for e in result.events if e.kind == "exception").traceback
    assert "KeyError: 0" in tb and "direct cause" in tb and "line 6, in step" in tb


def test_one_value_returned_names_the_return_line(here: Path) -> None:
    result = run_file(here, "one.py", """\
        import math


        def step(robot):
            x, y, theta = robot.pose
            gx, gy = robot.goal
            speed = min(0.5, math.hypot(gx - x, gy - y))
            if speed < 0.1:
                return 0.0, theta
            return speed
        """)
    assert result.error == ("InvalidOutput in robot 0 at t=0 s, one.py:10: step() must return "
                            "(speed_ref, heading_ref), two numbers; got 0.5 (a float)\n"
                            "    return speed")


def test_running_off_the_end_names_the_def_line(here: Path) -> None:
    result = run_file(here, "none.py", """\
        def step(robot):
            x, y, theta = robot.pose
            if x > 100:
                return 0.5, 0.0
        """)
    assert result.error == ("InvalidOutput in robot 0 at t=0 s, none.py:1: step() must return "
                            "(speed_ref, heading_ref), two numbers; got None (it ended without "
                            "returning a value)\n    def step(robot):")


def test_nan_from_a_class_names_its_return_line(here: Path) -> None:
    result = run_file(here, "wobbly.py", """\
        import math


        class Wobbly:
            def reset(self, robot):
                self.speed = math.nan

            def step(self, robot):
                if robot.id > 5:
                    return 0.1, 0.0, 0.0
                return self.speed, 0.0
        """, policy="deactivate")
    failures = [e for e in result.events if e.kind == "exception"]
    assert [e.robot for e in failures] == [0, 1]
    assert failures[0].detail == ("Exception: InvalidOutput: robot 0: step() returned a "
                                  "non-finite reference (speed_ref=nan, heading_ref=0.0) "
                                  "(wobbly.py:11)")


def test_a_team_step_error_names_its_line(here: Path) -> None:
    result = run_file(here, "team.py", """\
        import numpy as np


        def team_step(team):
            speeds = np.full(len(team.ids), 0.5)
            return speeds, team.heading_of_goal
        """)
    assert result.error.startswith("AttributeError in the team algorithm at t=0 s, team.py:6: ")
    assert result.error.endswith("\n    return speeds, team.heading_of_goal")


def test_a_reset_error_names_its_line(here: Path) -> None:
    result = run_file(here, "reset.py", """\
        def reset(robot):
            robot.memory["target"] = robot.goal[2]


        def step(robot):
            return 0.5, 0.0
        """)
    assert result.error == ("IndexError in robot 0 at t=0 s, reset.py:2: tuple index out of "
                            "range\n"
                            "    robot.memory[\"target\"] = robot.goal[2]")


def test_an_import_error_names_the_line(here: Path) -> None:
    (here / "broken.py").write_text("import math\nX = undefined_name\n\n\ndef step(robot):\n"
                                    "    return 0.5, 0.0\n")
    with pytest.raises(mimics.MimicsError, match=r"broken.py, line 2: importing it raised "
                                                 r"NameError: name 'undefined_name'"):
        find_algorithm(str(here / "broken.py"))


def test_a_file_outside_the_working_folder_is_named_by_its_full_path(tmp_path: Path) -> None:
    result = run_file(tmp_path, "my_algo.py", MISSPELLED)
    assert f", {tmp_path / 'my_algo.py'}:6: " in result.error


def two_returns(robot):
    if robot.id:
        return 1.0
    return 0.5, 0.0


def many_returns(robot):
    if robot.id == 1:
        return robot.x
    if robot.id == 2:
        return None
    if robot.id == 3:
        return [1.0, 2.0, 3.0]
    return robot.y


def two_pairs(robot):
    if robot.id:
        return 0.0, robot.theta
    return robot.speed, 1.5


def test_literals_in_a_returned_pair_rule_a_return_out() -> None:
    first = two_pairs.__code__.co_firstlineno
    assert [p.line for p in return_lines(two_pairs, (math.nan, 1.5))] == [first + 3]
    # no return fits (forms misjudged): all are named rather than none
    assert [p.line for p in return_lines(two_pairs, (math.nan, 0.2))] == [first + 2, first + 3]
    assert [p.line for p in return_lines(two_pairs, (0.0, math.nan))] == [first + 2]
    assert [p.line for p in return_lines(two_pairs, (0.0, 1.5))] == [first + 2, first + 3]


def test_return_lines_keeps_the_returns_that_fit_the_output() -> None:
    first = two_returns.__code__.co_firstlineno
    assert [p.line for p in return_lines(two_returns, 1.0)] == [first + 2]
    many = many_returns.__code__.co_firstlineno
    assert [p.line for p in return_lines(many_returns, 3.0)] == [many + 2, many + 7]
    # it always ends in a return: None comes from one of them, not from running off its end
    assert [p.line for p in return_lines(many_returns, None)] == [many + 2, many + 4, many + 7]
    assert [p.line for p in return_lines(many_returns, [1, 2, 3])] == [many + 2, many + 6,
                                                                      many + 7]
    assert return_lines(many_returns, 1.0)[0].text == "return robot.x"
    assert return_lines(math.atan2, 1.0) == []  # no Python source: nothing to name


def test_only_mimics_internals_and_libraries_are_not_user_files() -> None:
    import numpy

    import mimics.algorithms.go_to_goal
    import mimics.engine.user_code.controllers

    assert not is_user_file(mimics.engine.user_code.controllers.__file__)
    assert not is_user_file(numpy.__file__)
    assert not is_user_file(math.__spec__.origin or "<built-in>")
    assert is_user_file(mimics.algorithms.go_to_goal.__file__)  # examples users copy
    assert is_user_file(__file__)
