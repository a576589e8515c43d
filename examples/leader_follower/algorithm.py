"""Leader-follower formation: robot 0 drives to its goal, the others keep their places.

Sensors: the comms matrix (the leader's position, heading and speed), the
pose, the goal (the leader's only).

Each follower's place is fixed in the leader's frame (behind it, in a V). A
follower steers to where its place is now plus where the leader is heading,
and matches the leader's speed, adding a correction proportional to its
distance from its place.
"""

import numpy as np

LEADER = 0
PLACES = {1: (-1.2, 1.0), 2: (-1.2, -1.0), 3: (-2.4, 0.0)}  # (behind, left) in leader's frame
GAIN = 0.8  # 1/s: speed added per metre of distance from the place
LOOKAHEAD = 1.0  # s: aim where the place will be this long from now


def _leader(robot):
    rows = robot.comms[robot.comms[:, 0] == LEADER]
    return rows[0] if len(rows) else None


def step(robot):
    """The leader goes to its goal; a follower tracks its place in the formation."""
    x, y, theta = robot.pose
    if robot.id == LEADER:
        gx, gy = robot.goal
        heading = np.arctan2(gy - y, gx - x)
        # at most 60% of top speed, so that followers have room to catch up
        return 0.6 * robot.type.max_speed * max(np.cos(heading - theta), 0.0), heading
    leader = _leader(robot)
    if leader is None or robot.id not in PLACES:  # no leader in range (or arrived): wait
        return 0.0, theta
    _, lx, ly, ltheta, lv, _ = leader
    behind, left = PLACES[robot.id]
    cos, sin = np.cos(ltheta), np.sin(ltheta)
    place = np.array([lx + cos * behind - sin * left, ly + sin * behind + cos * left])
    target = place + LOOKAHEAD * lv * np.array([cos, sin])
    dx, dy = target - (x, y)
    heading = np.arctan2(dy, dx)
    error = np.hypot(*(place - (x, y)))
    speed = min(robot.type.max_speed, lv + GAIN * error) * max(np.cos(heading - theta), 0.0)
    robot.log(f"{error:.2f} m from its place")
    return speed, heading
