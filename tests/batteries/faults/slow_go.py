"""go_to_goal that also sleeps 10 ms per call: same results, runs that take time."""

import math
import time


def step(robot):
    time.sleep(0.01)
    x, y, _ = robot.pose
    gx, gy = robot.goal
    return 1.0, math.atan2(gy - y, gx - x)
