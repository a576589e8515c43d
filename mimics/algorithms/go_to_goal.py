"""Drive straight to the goal at full speed, turning on the spot first if needed.

The paper's "simple algorithm to drive the robots to their goals" (section 4).
It ignores obstacles: see ``wall_aware`` for one that does not.
"""

import math


def step(robot):
    """Head for the goal; full speed when facing it, slower the more it is off."""
    goal = robot.goal  # read once: it is a property
    if goal is None:
        return 0.0, robot.heading
    x, y, theta = robot.pose.tolist()  # Python floats: the same values, quicker to add
    gx, gy = goal
    heading = math.atan2(gy - y, gx - x)  # math on floats: no NumPy scalar overhead
    alignment = math.cos(heading - theta)
    return robot.type.max_speed * max(alignment, 0.0), heading
