"""Ends the whole process with os._exit(3) at its first step."""

import os


def step(robot):
    os._exit(3)
