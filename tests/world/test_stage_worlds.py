"""Reading robot poses from Stage world files."""

import math
from pathlib import Path

import pytest

from mimics.world.stage_worlds import read_stage_world, stage_robot_poses
from tests.file_errors import file_error
from tests.stage import stage_file

SMALL = '''# a world
include "map.inc"
define bot position ( size [0.1 0.1 0.1] ranger ( ir( pose [0 0 0 90] ) ) )
define redbot bot ( color "red" )
window ( size [100 100] scale 10 )
floorplan ( size [16 16 0.5] pose [0 0 0 0] bitmap "x.png" )
model ( pose [1 1 0 0] )
redbot( name "a" pose [ 1.5 -2 0 90 ] )
bot ( pose [3 4 45] )   # Stage 2 poses have three values
#redbot( name "b" pose [ 5 6 0 180 ] )
# bot has a comment mentioning ( parentheses )
'''


def test_small_world(tmp_path: Path) -> None:
    path = tmp_path / "small.world"
    path.write_text(SMALL)
    world = read_stage_world(path)
    assert [(r.model, r.name, r.x, r.y) for r in world.robots] == [
        ("redbot", "a", 1.5, -2.0), ("bot", None, 3.0, 4.0)]
    assert world.robots[0].yaw == pytest.approx(math.pi / 2)
    assert world.robots[1].yaw == pytest.approx(math.pi / 4)
    assert world.floorplan is not None and world.floorplan["size"] == (16.0, 16.0, 0.5)
    with_commented = read_stage_world(path, include_commented=True)
    assert [r.name for r in with_commented.robots] == ["a", None, "b"]
    assert with_commented.robots[2].commented and with_commented.robots[2].line == 10


@pytest.mark.parametrize(("text", "expected"), [
    ("bot ( pose [1 2 0 0 )\n", "inside"),
    ("bot ( pose [1 2 0 0]\n\n", "never closed"),
    ("bot ( pose [a b c d] )\n", "pose must be"),
    (")\n", "unexpected '\\)'"),
    ("define bot\n", "expected 'define NAME BASE"),
])
def test_syntax_errors_name_file_and_line(tmp_path: Path, text: str, expected: str) -> None:
    path = tmp_path / "bad.world"
    file_error(read_stage_world, path, text, match=expected, line=1)
    # below a comment and a blank line, the same error is on line 3
    file_error(read_stage_world, path, "# a world\n\n" + text, match=expected, line=3)


def test_benchmark_worlds() -> None:
    cave, hospital = stage_file("cave.world"), stage_file("hospital.world")
    poses = stage_robot_poses(cave)
    assert poses.shape == (100, 3)
    assert poses[0].tolist() == pytest.approx([-5.285, 4.915, math.radians(150.459)])
    assert poses[:, 0].min() == pytest.approx(-7.652) and poses[:, 1].max() == pytest.approx(7.494)
    assert stage_robot_poses(hospital).shape == (1000, 3)
    both = stage_robot_poses(hospital, include_commented=True)
    assert both.shape == (2000, 3)
    assert both[1000].tolist() == [0.0, -15.0, 0.0] and both[-1].tolist() == [49.75, -14.0, 0.0]
    assert (both[:, 2] == 0).all()
