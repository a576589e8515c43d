"""Crashes the interpreter (a SIGSEGV sent to itself) at its first step. (ctypes, the
other way to a null-pointer read, is refused to user code in battery workers.)"""

import os
import signal


def step(robot):
    os.kill(os.getpid(), signal.SIGSEGV)
    return 1.0, 0.0
