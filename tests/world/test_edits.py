"""Edits as plain data (mimics.world.edits) and as ``[[edits]]`` tables of scenario files:
strict reading with one-line errors naming the field, and writing that reads back equal."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.world.edits import (
    EDIT_KINDS,
    END_STATUSES,
    Edit,
    EditError,
    edit_from_dict,
    nearest_wall,
    point_segment_distances,
)
from mimics.world.errors import ScenarioError
from mimics.world.scenario_files import load_scenario_toml, scenario_to_toml
from mimics.world.scenario_writer import edits_to_toml


@pytest.mark.parametrize(("data", "message"), [
    ({"kind": "teleport"}, "edit.kind: expected one of move_robot, add_wall, remove_wall, "
                           "set_goal, remove_robot, end, got 'teleport'"),
    ({"robot": 1}, "edit.kind: expected one of"),
    ({"kind": "move_robot", "robot": 0, "x": "abc", "y": 1.0}, "edit.x: expected a number, "
                                                              "got 'abc'"),
    ({"kind": "move_robot", "robot": 0, "x": 1.0}, "edit: missing field 'y' for move_robot"),
    ({"kind": "move_robot", "robot": -1, "x": 1.0, "y": 1.0},
     "edit.robot: expected a whole number >= 0, got -1"),
    ({"kind": "move_robot", "robot": True, "x": 1.0, "y": 1.0},
     "edit.robot: expected a whole number >= 0, got True"),
    ({"kind": "set_goal", "robot": 0, "x": math.nan, "y": 1.0},
     "edit.x: expected a number, got nan"),
    ({"kind": "set_goal", "robot": 0, "x": 1.0, "y": 1.0, "yaw": 0.0},
     "edit.yaw: unknown field for set_goal (expected one of kind, step, robot, x, y)"),
    ({"kind": "remove_robot", "robot": 0, "step": 1.5},
     "edit.step: expected a whole number >= 0, got 1.5"),
    ({"kind": "add_wall"}, "edit: expected exactly one of segment or rectangle for add_wall, "
                           "got neither"),
    ({"kind": "add_wall", "segment": [0, 0, 1, 1], "rectangle": [0, 0, 1, 1]},
     "got segment and rectangle"),
    ({"kind": "add_wall", "segment": [0, 0, 1]}, "edit.segment: expected [x1, y1, x2, y2], "
                                                 "got [0, 0, 1]"),
    ({"kind": "add_wall", "segment": [1, 1, 1, 1]}, "edit.segment: expected two different ends"),
    ({"kind": "add_wall", "rectangle": [2, 0, 1, 1]},
     "edit.rectangle: expected xmin < xmax and ymin < ymax, got [2.0, 0.0, 1.0, 1.0]"),
    ({"kind": "remove_wall", "at": [1.0]}, "edit.at: expected [x, y], got [1.0]"),
    ({"kind": "remove_wall", "wall": "3"}, "edit.wall: expected a whole number >= 0, got '3'"),
    ("move", "edit: expected a table with a kind, got 'move'"),
])
def test_malformed_edits_are_one_line_errors_naming_the_field(data, message):
    with pytest.raises(EditError) as error:
        edit_from_dict(data)
    assert message in str(error.value)
    assert "\n" not in str(error.value)
    assert isinstance(error.value, ScenarioError)  # the CLI's one-line error, exit status 2


def test_a_rectangle_is_its_four_sides_and_a_segment_itself():
    box = edit_from_dict({"kind": "add_wall", "rectangle": [1, 2, 4, 3]})
    sides = box.wall_segments().tolist()
    assert sides == [[1, 2, 4, 2], [4, 2, 4, 3], [4, 3, 1, 3], [1, 3, 1, 2]]
    # the sides close the loop: each ends where the next begins
    assert all(sides[k][2:] == sides[(k + 1) % 4][:2] for k in range(4))
    one = edit_from_dict({"kind": "add_wall", "segment": [0, 0, 2, 1]})
    assert one.wall_segments().tolist() == [[0, 0, 2, 1]]


numbers = st.floats(-50, 50, allow_nan=False)


@st.composite
def edits(draw: st.DrawFn) -> Edit:
    kind = draw(st.sampled_from(EDIT_KINDS))
    step = draw(st.integers(0, 10_000))
    if kind == "move_robot":
        yaw = draw(st.none() | numbers)
        return Edit(kind, step, robot=draw(st.integers(0, 9)), x=draw(numbers), y=draw(numbers),
                    yaw=yaw)
    if kind == "set_goal":
        return Edit(kind, step, robot=draw(st.integers(0, 9)), x=draw(numbers), y=draw(numbers))
    if kind == "remove_robot":
        return Edit(kind, step, robot=draw(st.integers(0, 9)))
    if kind == "end":
        return Edit(kind, step, status=draw(st.sampled_from(END_STATUSES)))
    if kind == "remove_wall":
        if draw(st.booleans()):
            return Edit(kind, step, wall=draw(st.integers(0, 99)))
        return Edit(kind, step, at=(draw(numbers), draw(numbers)))
    x0, y0 = draw(numbers), draw(numbers)
    w, h = draw(st.floats(0.01, 5)), draw(st.floats(0.01, 5))
    if draw(st.booleans()):
        return Edit(kind, step, rectangle=(x0, y0, x0 + w, y0 + h))
    return Edit(kind, step, segment=(x0, y0, x0 + w, y0 - h))


@settings(max_examples=60, deadline=None)
@given(st.lists(edits(), max_size=5))
def test_edits_written_as_toml_read_back_equal(timeline):
    for edit in timeline:
        assert edit_from_dict(edit.to_dict()) == edit
    text = "\n".join(edits_to_toml(tuple(timeline)))
    tables = tomllib.loads(text).get("edits", [])
    assert [edit_from_dict(table) for table in tables] == timeline


SCENARIO = '''
map = { segments = [[0.0, -2.0, 0.0, 2.0]], bounds = [-10.0, -10.0, 10.0, 10.0] }
robots = [
  { type = "Pioneer2DX", x = 2.0, y = 0.0 },
  { type = "Pioneer2DX", x = 4.0, y = 0.0, goal = [8.0, 0.0] },
]
'''


def write(tmp_path: Path, edits_text: str) -> Path:
    path = tmp_path / "s.toml"
    path.write_text(SCENARIO + edits_text)
    return path


def test_scenario_file_edits_are_read_in_step_order(tmp_path):
    path = write(tmp_path, '''
[[edits]]
step = 30
kind = "add_wall"
rectangle = [5.0, 3.0, 6.0, 4.0]

[[edits]]
step = 10
kind = "set_goal"
robot = 0
x = -5.0
y = 1.0
''')
    scenario = load_scenario_toml(path)
    assert [(e.step, e.kind) for e in scenario.edits] == [(10, "set_goal"), (30, "add_wall")]
    assert scenario.edits[1].rectangle == (5.0, 3.0, 6.0, 4.0)
    # written and read back: the same edits
    again = tmp_path / "again.toml"
    again.write_text(scenario_to_toml(scenario))
    assert load_scenario_toml(again).edits == scenario.edits


@pytest.mark.parametrize(("edits_text", "message"), [
    ('[[edits]]\nstep = 3\nkind = "remove_robot"\nrobot = 2\n',
     "line 7: edits[0].robot: no robot 2 (the scenario has 2: 0 to 1)"),
    ('[[edits]]\nkind = "remove_robot"\nrobot = 0\n\n[[edits]]\nkind = "set_goal"\nrobot = 1\n'
     'x = 30.0\ny = 0.0\n',
     "line 11: edits[1]: (30, 0) is outside the map bounds (-10, -10, 10, 10)"),
    ('[[edits]]\nkind = "move_robot"\nrobot = 0\nx = 1.0\ny = "up"\n',
     "line 7: edits[0].y: expected a number, got 'up'"),
    ('edits = 3\n', "edits: expected a list of edit tables"),
])
def test_scenario_file_edit_errors_name_the_file_line_and_field(tmp_path, edits_text, message):
    path = write(tmp_path, edits_text)
    with pytest.raises(ScenarioError) as error:
        load_scenario_toml(path)
    assert str(error.value).startswith(str(path))
    assert message in str(error.value)


# micrometres: shapely's distance to a segment of 1e-300 m is inf, not the reference here
coordinates = st.floats(-50, 50, allow_nan=False).map(lambda v: round(v, 6))


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(coordinates, coordinates, coordinates, coordinates), min_size=1,
                max_size=6), coordinates, coordinates)
def test_point_to_wall_distances_match_shapely(walls, px, py):
    segments = np.array(walls)
    ours = point_segment_distances(px, py, segments)
    point = shapely.Point(px, py)
    truth = [point.distance(shapely.LineString([(x1, y1), (x2, y2)])) if (x1, y1) != (x2, y2)
             else point.distance(shapely.Point(x1, y1)) for x1, y1, x2, y2 in walls]
    assert ours == pytest.approx(truth, abs=1e-9)
    nearest = nearest_wall(segments, (px, py))
    if min(truth) > 1.0:
        assert nearest is None
    else:
        assert nearest is not None and truth[nearest] == pytest.approx(min(truth), abs=1e-9)
