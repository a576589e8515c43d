"""Go to the goal along the laser's clear path nearest to it; keep right when robots come near.

Each step the robot tries headings outward from its goal direction, right
before left (6 degrees apart, up to 90 degrees off), and takes the first whose
path (a band the robot's width plus a margin, ``LOOKAHEAD`` m long) is clear
of every laser hit: walls and robots alike, as the laser sees both. When no
path in sight is clear it takes the one with the most room. It slows down as
the room ahead shrinks and stops ``STOP`` m short of what is in front.

The side-passing rule: when another robot (from ``robot.comms``) is within
``KEEP_RIGHT_RANGE`` m and 45 degrees of its nose, the robot aims
``KEEP_RIGHT`` to the right of its goal. Everyone applies the same rule, so
robots meeting head-on pass each other on the left, and a crowd heading for
one spot turns into a roundabout.

What it achieves (``tests/algorithms/test_builtins_behaviour.py``):
``circle_swap``, 8 robots: all reach their goals, no collision, in about 52 s;
``corridor``, 10 robots crossing in a 3 m corridor: no collision, 9 reach
their goals within 300 s and one ends in deadlock. It sees only in front:
the laser's field of view bounds the headings tried.
"""

import numpy as np

LOOKAHEAD = 2.0  # m of clear path wanted ahead
MARGIN = 0.15  # m of clearance on each side of the robot's path
STOP = 0.3  # m: stop when the room ahead falls to this
KEEP_RIGHT = np.radians(35)  # aim this far right of the goal when a robot is ahead...
KEEP_RIGHT_RANGE = 4.0  # ...within this many metres (and 45 degrees of the nose)
OFFSETS = np.radians(np.arange(6, 91, 6))
# headings tried, relative to the aim: straight, then right before left
TRIES = np.concatenate([[0.0], np.column_stack([-OFFSETS, OFFSETS]).ravel()])


def step(robot):
    """Head along the clear path nearest the goal direction; slow down as room runs out."""
    if robot.goal is None:
        return 0.0, robot.heading
    x, y, theta = robot.pose
    gx, gy = robot.goal
    aim = np.arctan2(gy - y, gx - x) - (KEEP_RIGHT if _robot_ahead(robot) else 0.0)

    ranges, angles = robot.scan.ranges, robot.scan.angles
    hit = ranges < robot.scan.max_range
    hit_x, hit_y = ranges[hit] * np.cos(angles[hit]), ranges[hit] * np.sin(angles[hit])
    # each try relative to the robot's heading, and the hits in the frame of each try
    tries = np.angle(np.exp(1j * (aim + TRIES - theta)))
    cos, sin = np.cos(tries)[:, None], np.sin(tries)[:, None]
    along = hit_x[None] * cos + hit_y[None] * sin
    across = hit_y[None] * cos - hit_x[None] * sin
    in_band = (along > -robot.type.length / 2) & (np.abs(across) < robot.type.width / 2 + MARGIN)
    # to the first hit on each path (inf when the laser sees nothing at all)
    room = np.where(in_band, along, np.inf).min(axis=1, initial=np.inf)
    wanted = min(LOOKAHEAD, np.hypot(gx - x, gy - y) + robot.type.width)
    in_sight = np.abs(tries) < np.max(np.abs(angles))
    if not in_sight.any():  # the aim is behind: turn toward it on the spot
        return 0.0, theta + tries[0]
    clear = in_sight & (room > wanted)
    best = int(np.argmax(clear)) if clear.any() else int(np.argmax(np.where(in_sight, room, -1)))

    nose = np.where(np.abs(angles) < np.pi / 3, ranges, np.inf).min()
    ahead = min(room[best], wanted, nose + 0.2)
    caution = np.clip((ahead - STOP) / (LOOKAHEAD - STOP), 0.0, 1.0)
    alignment = max(np.cos(tries[best]), 0.0) ** 4
    return robot.type.max_speed * alignment * caution, theta + tries[best]


def _robot_ahead(robot) -> bool:
    """Whether another robot is within KEEP_RIGHT_RANGE and 45 degrees of the nose."""
    others = robot.comms
    others = others[others[:, 0] != robot.id]
    x, y, theta = robot.pose
    dx, dy = others[:, 1] - x, others[:, 2] - y
    bearing = np.angle(np.exp(1j * (np.arctan2(dy, dx) - theta)))
    return bool(np.any((np.hypot(dx, dy) < KEEP_RIGHT_RANGE) & (np.abs(bearing) < np.pi / 4)))
