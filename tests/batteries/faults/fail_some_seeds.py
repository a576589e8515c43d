"""Heads for the goal, but on some seeds (robot 0's first random draw below 0.4) raises at
its first step: a run of the battery that fails as a whole under the abort policy."""

import math


def step(robot):
    if "draw" not in robot.memory:
        robot.memory["draw"] = robot.rng.random()
        if robot.id == 0 and robot.memory["draw"] < 0.4:
            raise RuntimeError("this seed fails")
    x, y, _ = robot.true_pose
    gx, gy = robot.goal
    return 1.0, math.atan2(gy - y, gx - x)
