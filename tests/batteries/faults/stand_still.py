"""A robot that never moves: with fixed start poses, every seed gives the same run (the
steady cell of the stopping-rule tests and the copies of the identical-seed warning)."""


def step(robot):
    return 0.0, 0.0
