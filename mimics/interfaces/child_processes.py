"""Child processes that end with the process that started them, even when it is killed."""

from __future__ import annotations

import shutil
import sys


def dying_with_parent(command: list[str]) -> list[str]:
    """``command`` made to be killed by the kernel when this process dies (Linux).

    util-linux's ``setpriv --pdeathsig`` sets ``PR_SET_PDEATHSIG`` before it
    runs the command: unlike a ``preexec_fn``, safe in a process with threads
    (rospy's, Numba's).
    """
    setpriv = shutil.which("setpriv") if sys.platform.startswith("linux") else None
    return [setpriv, "--pdeathsig", "KILL", "--", *command] if setpriv else command
