"""random_speed that also sleeps 5 ms per call: runs that vary with the seed and take time."""

import math
import time


def step(robot):
    time.sleep(0.005)
    if "speed" not in robot.memory:
        robot.memory["speed"] = float(robot.rng.uniform(0.3, 1.0))
    x, y, _ = robot.pose
    gx, gy = robot.goal
    return robot.memory["speed"], math.atan2(gy - y, gx - x)
