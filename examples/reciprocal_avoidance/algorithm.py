"""Reciprocal collision avoidance for many robots crossing (in the spirit of ORCA/RVO).

Sensors: the communication matrix (other robots' positions and velocities),
the laser (walls), the pose and the goal.

Each robot scores candidate velocities: how far each is from the velocity it
prefers (straight to its goal), plus a penalty that grows as the time to the
first collision with a neighbour shrinks. Avoidance is *reciprocal*: a robot
assumes its neighbour takes half of the effort, so it tests ``2 v - v_now``
against the neighbour's velocity (van den Berg et al., RVO, 2008). Everyone
also keeps to the right of the others, a shared rule that breaks the symmetry of
head-on meetings. The chosen velocity becomes a speed and heading reference.
"""

import numpy as np

HORIZON = 4.0  # m: neighbours farther than this are ignored
MARGIN = 0.15  # m added to the robots' radii
URGENCY = 1.5  # weight of 1 / (time to collision)
RIGHT_BIAS = 0.15  # weight that favours passing on the right
DIRECTIONS = np.linspace(-np.pi, np.pi, 24, endpoint=False)
FRACTIONS = np.array([0.25, 0.5, 0.75, 1.0])


def _candidates(max_speed: float, preferred: np.ndarray) -> np.ndarray:
    speeds = np.outer(FRACTIONS * max_speed, np.ones_like(DIRECTIONS)).ravel()
    angles = np.tile(DIRECTIONS, FRACTIONS.size)
    grid = np.column_stack([speeds * np.cos(angles), speeds * np.sin(angles)])
    return np.vstack([preferred, grid, np.zeros((1, 2))])


def _time_to_collision(relative_position, relative_velocity, radius):
    """Time until two discs at ``relative_position`` touch, per candidate (inf if never)."""
    a = np.sum(relative_velocity**2, axis=-1)
    b = np.sum(relative_position * relative_velocity, axis=-1)
    c = np.sum(relative_position**2, axis=-1) - radius**2
    disc = b * b - a * c
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (-b - np.sqrt(np.maximum(disc, 0.0))) / a
    t = np.where((disc > 0) & (b < 0) & (a > 1e-12), t, np.inf)
    return np.where(c <= 0, 0.0, np.maximum(t, 0.0))  # already touching: now


def step(robot):
    """Pick the velocity that balances going to the goal and not meeting anyone."""
    if robot.goal is None:
        return 0.0, robot.heading
    x, y, theta = robot.pose
    v_now = robot.velocity[0] * np.array([np.cos(theta), np.sin(theta)])
    to_goal = np.array(robot.goal) - (x, y)
    distance = np.hypot(*to_goal)
    max_speed = robot.type.max_speed
    preferred = to_goal / max(distance, 1e-9) * min(max_speed, distance)
    candidates = _candidates(max_speed, preferred)
    cost = np.hypot(*(candidates - preferred).T)

    radius = 2 * (np.hypot(robot.type.length, robot.type.width) / 2 + MARGIN)
    others = robot.comms[robot.comms[:, 0] != robot.id]
    offsets = others[:, 1:3] - (x, y)
    near = np.hypot(offsets[:, 0], offsets[:, 1]) < HORIZON
    offsets, others = offsets[near], others[near]
    if len(others):
        v_others = others[:, 4:5] * np.column_stack([np.cos(others[:, 3]), np.sin(others[:, 3])])
        # (candidates, neighbours, 2): each candidate's velocity relative to each neighbour
        relative = (2 * candidates - v_now)[:, None, :] - v_others[None, :, :]
        ttc = _time_to_collision(-offsets[None, :, :], relative, radius)
        cost += np.sum(URGENCY / np.maximum(ttc, 1e-3), axis=1)
        # keep right: passing a neighbour ahead on its left costs a little more
        ahead = offsets @ preferred > 0
        cross = np.outer(candidates[:, 1], offsets[ahead, 0]) - np.outer(candidates[:, 0],
                                                                          offsets[ahead, 1])
        cost += RIGHT_BIAS * np.sum(cross < 0, axis=1)

    # walls: a candidate heading into a wall closer than a second of travel is ruled out
    ranges, angles = robot.scan.ranges, robot.scan.angles
    headings = np.angle(np.exp(1j * (np.arctan2(candidates[:, 1], candidates[:, 0]) - theta)))
    beam = np.clip(np.searchsorted(angles, headings), 0, angles.size - 1)  # angles ascend
    facing = (headings >= angles[0]) & (headings <= angles[-1])
    speeds = np.hypot(candidates[:, 0], candidates[:, 1])
    blocked = facing & (ranges[beam] < robot.type.length / 2 + speeds * 1.0 + MARGIN)
    cost[blocked & (speeds > 0)] = np.inf

    best = candidates[np.argmin(cost)]
    speed = np.hypot(*best)
    if speed < 1e-9:
        return 0.0, theta
    heading = np.arctan2(best[1], best[0])
    return speed * max(np.cos(heading - theta), 0.0), heading
