"""Drives east, and raises at its 7th step."""


def step(robot):
    robot.memory["calls"] = robot.memory.get("calls", 0) + 1
    if robot.memory["calls"] == 7:
        raise ValueError("boom at step 7")
    return 1.0, 0.0
