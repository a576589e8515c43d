"""Go to the goal, steering around walls and robots the laser sees (potential field).

Each beam that sees something closer than ``influence`` pushes the robot away
from it; the goal pulls. The robot heads along the sum and slows down when
something is close in front.
"""

import numpy as np

INFLUENCE = 1.5  # m: obstacles farther than this are ignored
REPULSION = 0.6  # weight of the obstacles against the goal's pull


def step(robot):
    """Head along goal attraction plus obstacle repulsion; slow down near obstacles."""
    if robot.goal is None:
        return 0.0, robot.heading
    x, y, theta = robot.pose
    gx, gy = robot.goal
    pull = np.array([gx - x, gy - y])
    pull /= max(np.hypot(*pull), 1e-9)

    ranges, angles = robot.scan.ranges, robot.scan.angles
    near = ranges < INFLUENCE
    directions = theta + angles[near]
    weights = (1.0 / np.maximum(ranges[near], 1e-3) - 1.0 / INFLUENCE) / near.size
    push = -np.array([np.sum(weights * np.cos(directions)), np.sum(weights * np.sin(directions))])

    total = pull + REPULSION * push
    heading = np.arctan2(total[1], total[0])
    front = np.abs(angles) < np.pi / 6
    clearance = ranges[front].min() if front.any() else robot.scan.max_range
    caution = np.clip((clearance - robot.type.length / 2) / INFLUENCE, 0.0, 1.0)
    alignment = max(np.cos(heading - theta), 0.0)
    return robot.type.max_speed * alignment * caution, heading
