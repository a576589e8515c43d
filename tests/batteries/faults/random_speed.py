"""go_to_goal at a speed drawn once per robot from ``robot.rng`` (seeded by the run's seed):
runs whose time to goal varies from seed to seed, whatever the scenario randomizes."""

import math


def step(robot):
    if "speed" not in robot.memory:
        robot.memory["speed"] = float(robot.rng.uniform(0.3, 1.0))
    x, y, _ = robot.pose
    gx, gy = robot.goal
    return robot.memory["speed"], math.atan2(gy - y, gx - x)
