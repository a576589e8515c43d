"""Go to the goal along the free path the laser shows nearest to it, passing on the right.

Each step the robot tries headings from the goal direction outward, right
before left (6 degrees apart, up to 90 degrees off), and takes the first whose
path (a band the robot's width plus a margin, ``LOOKAHEAD`` m long) is clear
of every laser hit: walls and robots alike, as the laser sees both. When no
path in sight is clear it takes the one with the most room. It slows down as
the room ahead (along its path and within 60 degrees of its nose) shrinks and
stops ``STOP`` m short. Two robots meeting head-on both turn right, so they
pass each other.

What it achieves (``tests/algorithms/test_builtins_behaviour.py``): it gets
round walls and robots that stand or drive by; in a crowd where everyone
heads for the same spot (``circle_swap``) the robots stop short of each other
and stay stuck (deadlocks, no collisions); in a two-way ``corridor`` some pass
and some still collide or stick. It sees only in front: the laser's field of
view bounds the headings tried.
"""

import numpy as np

LOOKAHEAD = 2.0  # m of clear path wanted ahead
MARGIN = 0.15  # m of clearance on each side of the robot's path
STOP = 0.3  # m: stop when the room ahead falls to this
OFFSETS = np.radians(np.arange(6, 91, 6))
# headings tried, relative to the goal direction: straight, then right before left
TRIES = np.concatenate([[0.0], np.column_stack([-OFFSETS, OFFSETS]).ravel()])


def step(robot):
    """Head along the clear path nearest the goal direction; slow down as room runs out."""
    if robot.goal is None:
        return 0.0, robot.heading
    x, y, theta = robot.pose
    gx, gy = robot.goal
    ranges, angles = robot.scan.ranges, robot.scan.angles
    hit = ranges < robot.scan.max_range
    hit_x, hit_y = ranges[hit] * np.cos(angles[hit]), ranges[hit] * np.sin(angles[hit])

    # each try, relative to the robot's heading, and the hits in its frame
    tries = np.angle(np.exp(1j * (np.arctan2(gy - y, gx - x) + TRIES - theta)))
    cos, sin = np.cos(tries)[:, None], np.sin(tries)[:, None]
    along = hit_x[None] * cos + hit_y[None] * sin
    across = hit_y[None] * cos - hit_x[None] * sin
    in_band = (along > -robot.type.length / 2) & (np.abs(across) < robot.type.width / 2 + MARGIN)
    room = np.where(in_band, along, np.inf).min(axis=1)  # to the first hit on each path
    wanted = min(LOOKAHEAD, np.hypot(gx - x, gy - y) + robot.type.width)
    in_sight = np.abs(tries) < np.max(np.abs(angles))
    if not in_sight.any():  # goal behind: turn toward it on the spot
        return 0.0, theta + tries[0]
    clear = in_sight & (room > wanted)
    best = int(np.argmax(clear)) if clear.any() else int(np.argmax(np.where(in_sight, room, -1)))

    nose = np.where(np.abs(angles) < np.pi / 3, ranges, np.inf).min()
    ahead = min(room[best], wanted, nose + 0.2)
    caution = np.clip((ahead - STOP) / (LOOKAHEAD - STOP), 0.0, 1.0)
    alignment = max(np.cos(tries[best]), 0.0) ** 4
    return robot.type.max_speed * alignment * caution, theta + tries[best]
