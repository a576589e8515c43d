"""Never returns from its first step, inside one long C call (no Python line runs to stop it)."""

import time


def step(robot):
    time.sleep(3600)
    return 1.0, 0.0
