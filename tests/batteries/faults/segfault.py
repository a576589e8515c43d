"""Crashes the interpreter (a null-pointer read through ctypes) at its first step."""

import ctypes


def step(robot):
    ctypes.string_at(0)
    return 1.0, 0.0
