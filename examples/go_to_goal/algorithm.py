"""Go to goal: turn toward the goal, drive when facing it, slow down on arrival.

Sensors: the pose (measured, noisy) and the goal. Nothing else: robots on
crossing paths will collide (see ``reciprocal_avoidance`` for one that does not).
"""

import numpy as np


def step(robot):
    """Speed and heading references toward the goal."""
    if robot.goal is None:  # deployment scenarios have no goals: stay
        return 0.0, robot.heading
    x, y, theta = robot.pose
    gx, gy = robot.goal
    heading = np.arctan2(gy - y, gx - x)  # absolute heading to the goal
    distance = np.hypot(gx - x, gy - y)
    facing = max(np.cos(heading - theta), 0.0)  # 1 when facing it, 0 when side-on or away
    speed = min(robot.type.max_speed, distance) * facing  # slow down in the last metre
    robot.log(f"{distance:.2f} m to go")
    return speed, heading
