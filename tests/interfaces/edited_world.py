"""A run edited as it ran, shared by the tests of its replay, plot, live view and workbench.

Two Pioneer2DX (SICK LMS200: 8 m, 180 beams over 180 degrees) drive along +x from
(0, 0) and (0, 4), heading 0, in a map with one wall from (6, -3) to (6, 3). The
scenario's timed edits: at step 3 a rectangle over robot 1 (refused: it would enclose
the robot), at step 5 a wall from (3, -1) to (3, 1) across robot 0's way, at step 8
robot 1 moved to (0, 6.5), at step 10 robot 0's goal set to (8, -2), at step 12 wall 0
(the one at x = 6) removed. 2 s at 0.1 s: steps 0 to 20, all recorded.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from mimics.records.runner import prepare, run_to_folder


def line_in_the_walled_room(count: int, spacing: float, time_limit: float) -> str:
    """The scenario file of ``count`` Pioneer2DX in a line along y from (0, 0), ``spacing``
    apart, heading for x = 9, in the room with one wall at x = 6, for ``time_limit`` s."""
    return f'''
name = "edited"
map = {{ segments = [[6.0, -3.0, 6.0, 3.0]], bounds = [-5.0, -5.0, 12.0, 8.0] }}

[[robots]]
generator = "line"
type = "Pioneer2DX"
count = {count}
start = [0.0, 0.0]
step = [0.0, {spacing}]
goal_offset = [9.0, 0.0]

[settings]
time_limit = {time_limit}
'''


SCENARIO = line_in_the_walled_room(2, 4.0, 2.0) + '''
[[edits]]
step = 3
kind = "add_wall"
rectangle = [-1.0, 3.0, 1.0, 5.0]

[[edits]]
step = 5
kind = "add_wall"
segment = [3.0, -1.0, 3.0, 1.0]

[[edits]]
step = 8
kind = "move_robot"
robot = 1
x = 0.0
y = 6.5

[[edits]]
step = 10
kind = "set_goal"
robot = 0
x = 8.0
y = -2.0

[[edits]]
step = 12
kind = "remove_wall"
wall = 0
'''

START_WALL = [6.0, -3.0, 6.0, 3.0]
ADDED_WALL = [3.0, -1.0, 3.0, 1.0]
#: The walls by hand: (first step, walls) for each change (the refused rectangle: none).
WALLS_BY_STEP = [(0, [START_WALL]), (5, [START_WALL, ADDED_WALL]), (12, [ADDED_WALL])]
ADDED_STEP, MOVE_STEP, MOVED_ROBOT, MOVED_TO = 5, 8, 1, (0.0, 6.5)
GOAL_STEP, NEW_GOAL = 10, [8.0, -2.0]  # robot 0's; its first goal: (9, 0)
START_GOALS = [[9.0, 0.0], [9.0, 4.0]]


def walls_at(step: int) -> list[list[float]]:
    """The walls shown at a frame of ``step`` (the edits of steps <= ``step`` applied)."""
    return [walls for first, walls in WALLS_BY_STEP if first <= step][-1]


def scenario_file(folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "edited.toml"
    path.write_text(SCENARIO)
    return path


def record_edited_run(folder: Path) -> Path:
    """Run the scenario (go_to_goal, seed 1) into ``folder``; returns it."""
    run_to_folder(prepare(scenario_file(folder.parent / "source"), "go_to_goal", seed=1),
                  folder, robot_logs="off")
    return folder


def beam_ends(segments: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each beam's direction (rad, world) and end point ``(b, 2)`` from segments ``(b, 2, 2)``
    or ``(b, 4)``."""
    segments = np.asarray(segments, dtype=np.float64).reshape(-1, 2, 2)
    along = segments[:, 1] - segments[:, 0]
    return np.arctan2(along[:, 1], along[:, 0]), segments[:, 1]


def through_added_wall(x: float, y: float, direction: np.ndarray) -> np.ndarray:
    """The beams from (x, y) that cross the added wall (x = 3, |y| <= 1), by hand, with a
    margin from its ends."""
    forward = np.cos(direction) > 0.1
    cross_y = y + (3.0 - x) * np.tan(direction)
    return forward & (np.abs(cross_y) < 0.95)
