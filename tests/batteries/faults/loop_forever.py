"""Never returns from its first step (a hang in user code)."""


def step(robot):
    while True:
        pass
