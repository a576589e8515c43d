"""Child processes that end with the process that started them, even when it is killed."""

from __future__ import annotations

import shutil


def dying_with_parent(command: list[str]) -> list[str]:
    """``command`` made to be killed by the kernel when this process dies (Linux).

    util-linux's ``setpriv --pdeathsig`` sets ``PR_SET_PDEATHSIG`` before it
    runs the command: unlike a ``preexec_fn``, safe in a process with threads
    (rospy's, Numba's).
    """
    from mimics.process_platform import has_death_signal

    setpriv = shutil.which("setpriv") if has_death_signal() else None
    return [setpriv, "--pdeathsig", "KILL", "--", *command] if setpriv else command
