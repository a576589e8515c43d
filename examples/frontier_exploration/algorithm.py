"""Frontier exploration: build an occupancy grid from the laser, drive to the nearest frontier.

Sensors: the laser and the pose (measured); the map is *not* used: each robot
learns it. A frontier is a known-free cell next to an unknown one (Yamauchi,
1997). Each robot keeps its own grid in ``robot.memory["grid"]`` (log-odds,
0 = unknown), plans a shortest path over known-free cells to the nearest
frontier (breadth-first search), and follows it, replanning every few seconds.
"""

from collections import deque

import numpy as np
from scipy.ndimage import binary_dilation

CELL = 0.1  # m per grid cell
FREE, OCCUPIED = -0.4, 0.85  # log-odds added for a beam passing through / ending in a cell
REPLAN = 3.0  # s between plans
MIN_FRONTIER = 0.8  # m: frontiers closer than this are skipped (the laser will see them)
LOOKAHEAD = 0.6  # m along the path to the waypoint the robot steers to
CRUISE = 0.35  # m/s
CLEARANCE = 0.3  # m kept between the robot and known walls when planning


def _cell(robot, xy):
    xmin, ymin = robot.map.bounds[:2]
    return (np.floor((np.asarray(xy)[..., 1] - ymin) / CELL).astype(int),
            np.floor((np.asarray(xy)[..., 0] - xmin) / CELL).astype(int))


def _mark(robot, grid, points, value):
    """Add ``value`` to the cells holding ``points`` (those inside the grid)."""
    rows, cols = _cell(robot, points)
    inside = (rows >= 0) & (rows < grid.shape[0]) & (cols >= 0) & (cols < grid.shape[1])
    np.add.at(grid, (rows[inside], cols[inside]), value)


def _update(robot, grid):
    """Mark cells along each beam free and the cell where it hit occupied."""
    x, y, theta = robot.pose
    ranges, angles = robot.scan.ranges, theta + robot.scan.angles
    direction = np.column_stack([np.cos(angles), np.sin(angles)])
    along = np.arange(0.0, robot.scan.max_range, CELL / 2)
    points = np.array([x, y]) + along[None, :, None] * direction[:, None, :]
    _mark(robot, grid, points[along[None, :] < ranges[:, None] - CELL / 2], FREE)
    hit = robot.scan.hits
    _mark(robot, grid, np.array([x, y]) + ranges[hit, None] * direction[hit], OCCUPIED)
    np.clip(grid, -4.0, 4.0, out=grid)


def _plan(robot, grid):
    """Cells of a shortest path from the robot to the nearest frontier, or None."""
    free, unknown = grid < -0.2, grid == 0.0
    radius = int(np.ceil((np.hypot(robot.type.length, robot.type.width) / 2 + CLEARANCE) / CELL))
    disc = np.hypot(*np.mgrid[-radius:radius + 1, -radius:radius + 1]) <= radius
    start = tuple(int(v) for v in _cell(robot, robot.pose[:2]))
    passable = free & ~binary_dilation(grid > 0.2, structure=disc)
    around = np.zeros_like(free)  # let the robot leave a spot too close to a wall
    around[max(start[0] - radius, 0):start[0] + radius + 1,
           max(start[1] - radius, 0):start[1] + radius + 1] = True
    passable |= free & around
    targets = passable & binary_dilation(free & binary_dilation(unknown), iterations=2)
    parent = {start: start}
    queue = deque([start])
    skip = (MIN_FRONTIER / CELL) ** 2
    while queue:
        cell = queue.popleft()
        if targets[cell] and (cell[0] - start[0]) ** 2 + (cell[1] - start[1]) ** 2 > skip:
            path = [cell]
            while path[-1] != start:
                path.append(parent[path[-1]])
            return path[::-1]
        r, c = cell
        for nxt in ((r + 1, c), (r - 1, c), (r, c + 1), (r, c - 1)):
            if (nxt not in parent and 0 <= nxt[0] < grid.shape[0] and 0 <= nxt[1] < grid.shape[1]
                    and passable[nxt]):
                parent[nxt] = cell
                queue.append(nxt)
    return None


def step(robot):
    """Map, (re)plan to the nearest frontier, and follow the path."""
    memory = robot.memory
    if "grid" not in memory:
        xmin, ymin, xmax, ymax = robot.map.bounds
        shape = (int(np.ceil((ymax - ymin) / CELL)), int(np.ceil((xmax - xmin) / CELL)))
        memory.update(grid=np.zeros(shape), path=None, planned=-np.inf)
    _update(robot, memory["grid"])
    x, y, theta = robot.pose
    if memory["path"] is None or robot.time - memory["planned"] >= REPLAN:
        memory["path"], memory["planned"] = _plan(robot, memory["grid"]), robot.time
        if memory["path"] is None:
            robot.log("no frontier left: exploration done")
    if not memory["path"]:
        return 0.0, theta
    xmin, ymin = robot.map.bounds[:2]
    cells = np.array(memory["path"])
    points = np.column_stack([xmin + (cells[:, 1] + 0.5) * CELL, ymin + (cells[:, 0] + 0.5) * CELL])
    distance = np.hypot(points[:, 0] - x, points[:, 1] - y)
    nearest = int(distance.argmin())
    ahead = np.nonzero(distance[nearest:] >= LOOKAHEAD)[0]
    if ahead.size == 0:  # at the end of the path: plan again next step
        memory["path"] = None
        return 0.0, theta
    wx, wy = points[nearest + ahead[0]]
    heading = np.arctan2(wy - y, wx - x)
    front = robot.scan.ranges[np.abs(robot.scan.angles) < np.pi / 4].min()
    if front < robot.type.length / 2 + 0.15:  # about to touch something: back off, replan
        memory["path"] = None
        return -0.1, theta
    return CRUISE * max(np.cos(heading - theta), 0.0) ** 2, heading
