"""The bridge's parts that need no ROS: the map's rasterisation and the command inbox."""

from __future__ import annotations

import threading
import time

import numpy as np
import pytest
import shapely

from mimics.interfaces.ros.inbox import HOLD, Command, Inbox, LockstepTimeout
from mimics.interfaces.ros.occupancy import FREE, OCCUPIED, rasterise
from mimics.world.errors import MimicsError
from mimics.world.maps import Map


def shapely_cells(segments: np.ndarray, bounds: tuple, resolution: float,
                  shape: tuple[int, int]) -> np.ndarray:
    """Independent truth: a cell is occupied when its square meets a segment."""
    xmin, ymin = bounds[0], bounds[1]
    lines = shapely.multilinestrings([[(x1, y1), (x2, y2)] for x1, y1, x2, y2 in segments])
    rows, columns = np.indices(shape)
    boxes = shapely.box(xmin + columns * resolution, ymin + rows * resolution,
                        xmin + (columns + 1) * resolution, ymin + (rows + 1) * resolution)
    return shapely.intersects(boxes, lines)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_cells_are_those_the_segments_cross(seed):
    rng = np.random.default_rng(seed)
    bounds = (-3.0, 1.0, 7.0, 8.0)
    starts = rng.uniform((-4, 0), (8, 9), (150, 2))  # some end outside the bounds
    ends = starts + rng.normal(0, 2.0, (150, 2)) * rng.choice([0.02, 1.0], (150, 1))
    segments = np.hstack([starts, ends])
    grid = rasterise(Map(segments, bounds), 0.25)
    assert grid.cells.shape == (28, 40) and grid.origin == (-3.0, 1.0)
    truth = shapely_cells(segments, bounds, 0.25, grid.cells.shape)
    np.testing.assert_array_equal(grid.cells == OCCUPIED, truth)
    assert set(np.unique(grid.cells)) <= {OCCUPIED, FREE}


def test_hand_computed_cells():
    world = Map([[0.05, 0.05, 0.35, 0.05],  # along row 0, columns 0 to 3
                 [0.52, 0.51, 0.58, 0.54],  # shorter than a cell: cell (5, 5)
                 [0.95, 0.15, 0.95, 0.42]],  # vertical in column 9, rows 1 to 4
                (0.0, 0.0, 1.0, 1.0))
    grid = rasterise(world, 0.1)
    expected = np.zeros((10, 10), dtype=bool)
    expected[0, 0:4] = True
    expected[5, 5] = True
    expected[1:5, 9] = True
    np.testing.assert_array_equal(grid.cells == OCCUPIED, expected)


def test_bounds_not_a_multiple_of_the_resolution_round_up():
    grid = rasterise(Map.empty((0.0, 0.0, 1.05, 0.5)), 0.1)
    assert (grid.height, grid.width) == (5, 11)
    assert not grid.cells.any()


@pytest.mark.parametrize("resolution", [0.0, -0.1, float("nan"), 1e-6])
def test_bad_resolutions_are_one_line_errors(resolution):
    with pytest.raises(MimicsError, match="map resolution"):
        rasterise(Map.box(10.0, 10.0), resolution)


# -- the inbox ---------------------------------------------------------------

def test_lockstep_takes_the_first_command_after_expect():
    inbox = Inbox(3, lockstep=True)
    inbox.deliver(0, Command("reference", 9.0, 9.0))  # before expect: nothing asked
    inbox.expect(4, [0, 1])
    inbox.deliver(0, Command("reference", 0.5, 0.1))
    inbox.deliver(0, Command("reference", 0.7, 0.2))  # a second one for the same step
    inbox.deliver(1, Command("twist", 0.3, -0.2, step=4))
    assert inbox.take(0, 4) == (
        Command("reference", 0.5, 0.1),
        ["dropped a second command for step 4 (lockstep takes the first)"])
    assert inbox.take(1, 4) == (Command("twist", 0.3, -0.2, step=4), [])


def test_lockstep_drops_stale_stamps_then_times_out():
    inbox = Inbox(1, lockstep=True, timeout=0.1)
    inbox.expect(7, [0])
    inbox.deliver(0, Command("reference", 0.5, 0.1, step=6))
    start = time.monotonic()
    with pytest.raises(LockstepTimeout):
        inbox.take(0, 7)
    assert time.monotonic() - start >= 0.1
    inbox.deliver(0, Command("reference", 0.4, 0.0, step=7))
    command, notes = inbox.take(0, 7)
    assert command == Command("reference", 0.4, 0.0, step=7)
    assert notes == ["dropped a cmd stamped for step 6 while waiting for step 7"]


def test_one_deadline_for_the_whole_step_naming_every_robot_still_waiting():
    inbox = Inbox(4, lockstep=True, timeout=0.1)
    inbox.expect(3, [0, 1, 2, 3])
    inbox.deliver(2, Command("reference", 0.5, 0.1))
    with pytest.raises(LockstepTimeout) as first:
        inbox.take(0, 3)
    assert first.value.robots == (0, 1, 3)
    # the step's deadline has passed for everyone: robot 1 does not get a time-out of its own
    inbox._ready.wait = None  # any wait would now fail loudly (TypeError)
    with pytest.raises(LockstepTimeout) as second:
        inbox.take(1, 3)
    assert second.value.robots == (0, 1, 3)
    assert inbox.take(2, 3)[0] == Command("reference", 0.5, 0.1)


def test_the_notes_of_one_step_merge_repeats_with_a_count():
    inbox = Inbox(1, lockstep=False)
    for _ in range(3):
        inbox.reject(0, "cmd_vel: bad")
    inbox.reject(0, "cmd: other")
    assert inbox.take(0, 0)[1] == ["cmd_vel: bad; holding the last reference (3 times)",
                                   "cmd: other; holding the last reference"]


def test_lockstep_waits_for_a_command_from_another_thread():
    inbox = Inbox(1, lockstep=True)
    inbox.expect(0, [0])
    sender = threading.Timer(0.05, inbox.deliver, (0, Command("reference", 0.2, 0.3)))
    sender.start()
    assert inbox.take(0, 0)[0] == Command("reference", 0.2, 0.3)
    sender.join()


def test_a_malformed_message_answers_the_step_with_hold():
    inbox = Inbox(1, lockstep=True)
    inbox.expect(2, [0])
    inbox.reject(0, "cmd: speed_ref must be a finite number, got nan")
    inbox.deliver(0, Command("reference", 0.5, 0.1))  # too late: the step is answered
    command, notes = inbox.take(0, 2)
    assert command is HOLD
    assert notes[0] == "cmd: speed_ref must be a finite number, got nan; holding the last reference"


def test_realtime_gives_the_latest_command_and_keeps_it():
    inbox = Inbox(2, lockstep=False)
    assert inbox.take(0, 0) == (None, [])
    inbox.deliver(0, Command("reference", 0.1, 0.0))
    inbox.deliver(0, Command("reference", 0.2, 0.0))
    inbox.reject(0, "cmd: expected data = ..., got 1 values")
    command, notes = inbox.take(0, 5)
    assert command == Command("reference", 0.2, 0.0)
    assert notes == ["cmd: expected data = ..., got 1 values; holding the last reference"]
    assert inbox.take(0, 6) == (Command("reference", 0.2, 0.0), [])
