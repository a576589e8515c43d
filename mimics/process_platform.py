"""The one switch for the process paths that differ between Linux, macOS and Windows.

Linux alone has ``PR_SET_PDEATHSIG`` (``prctl``, util-linux's ``setpriv``): there a
battery's workers and a first run's compile processes are killed by the kernel with the
process that started them, and a compile process may be a fork of the run. macOS has
no ``prctl``; Windows has neither ``prctl`` nor ``fork``, so its workers are ``spawn``
ed fresh interpreters. Everywhere a watcher thread also ends a worker whose parent is
gone (:mod:`mimics.batteries.workers`).

The paths read this module only, so that the other systems' paths can be run on Linux:
``MIMICS_PROCESS_PLATFORM=windows`` (or ``macos``) in the environment makes this process
and its children take them (the tests do; nothing else needs it).
"""

from __future__ import annotations

import os
import sys

from mimics.world.errors import MimicsError

#: The environment variable that makes Linux take another system's process paths.
PLATFORM_ENV = "MIMICS_PROCESS_PLATFORM"
FORCEABLE = ("macos", "windows")


def process_platform() -> str:
    """``"linux"``, ``"macos"``, ``"windows"`` or ``"other"`` (another POSIX system).

    Raises:
        MimicsError: :data:`PLATFORM_ENV` holds something other than macos or windows.
    """
    forced = os.environ.get(PLATFORM_ENV, "")
    if forced:
        if forced not in FORCEABLE:
            raise MimicsError(f"{PLATFORM_ENV}: expected one of {', '.join(FORCEABLE)} "
                              f"(or unset), got {forced!r}")
        return forced
    if sys.platform.startswith("linux"):
        return "linux"
    return {"darwin": "macos", "win32": "windows"}.get(sys.platform, "other")


def has_death_signal() -> bool:
    """Whether a child can be set to die with its parent (``PR_SET_PDEATHSIG``), and a
    compile process may be a fork of the run: Linux only."""
    return process_platform() == "linux"


def worker_start_method() -> str:
    """How a battery's worker processes start: ``forkserver`` where the system has it
    (Linux, macOS), else ``spawn`` (Windows)."""
    import multiprocessing  # here: the run's own start-up does without it

    if process_platform() == "windows":
        return "spawn"
    return "forkserver" if "forkserver" in multiprocessing.get_all_start_methods() else "spawn"
