"""C and C++ algorithms on the command line: ``mimics include-dir``, and runs that may crash.

``mimics run`` with a ``.c``/``.cpp`` algorithm runs the simulation in a child
Python process: compiled code that segfaults or aborts kills that child, not
the command, which then says in one line which signal ended it and in which
robot's call, and exits with status 1. A fresh interpreter rather than a
fork: the parent may already have started Numba's OpenMP threads, which a
forked child cannot use. The child (``single_run.child_main``) prints the summary
itself, so a run that does not crash looks exactly like any other.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

from mimics.interfaces.cli.output import fail, say

#: Set in the child: the ``run`` arguments as JSON (and the sign not to isolate again).
CHILD_ENV = "MIMICS_NATIVE_RUN"


def include_dir_command() -> None:
    """Print the folder holding mimics.h, for your own builds: cc -I"$(mimics include-dir)"."""
    from mimics.native.build import include_dir

    say(str(include_dir()))


def needs_child(algorithm: str) -> bool:
    """Whether ``mimics run`` should run ``algorithm`` in a child process."""
    from mimics.native import NATIVE_SUFFIXES

    return Path(algorithm).suffix.lower() in NATIVE_SUFFIXES and CHILD_ENV not in os.environ


def run_in_child(arguments: dict[str, Any]) -> int:
    """Run the ``run`` command with ``arguments`` in a child process; returns the exit status.

    A child killed by a signal is reported in one line (status 1); its own
    statuses (0, 2 for bad input...) are passed on.
    """
    from mimics.native.adapter import PROGRESS_ENV

    with tempfile.TemporaryDirectory(prefix="mimics-run-") as folder:
        progress = Path(folder) / "progress"
        progress.write_bytes((-1).to_bytes(8, "little", signed=True) * 2)
        plain = {key: str(value) if isinstance(value, Path) else value
                 for key, value in arguments.items()}
        env = {**os.environ, CHILD_ENV: json.dumps(plain), PROGRESS_ENV: str(progress)}
        code = "from mimics.interfaces.cli.single_run import child_main; child_main()"
        child = subprocess.Popen([sys.executable, "-c", code], env=env)
        status = _wait(child)
        if status >= 0:
            return status
        robot, step = (int.from_bytes(progress.read_bytes()[k:k + 8], "little", signed=True)
                       for k in (0, 8))
    number = -status
    if number == signal.SIGINT:
        fail("interrupted")
        return 130
    try:
        name = f"{signal.Signals(number).name} ({signal.strsignal(number)})"
    except ValueError:
        name = f"signal {number}"
    where = f" in robot {robot}'s call at step {step}" if robot >= 0 else ""
    fail(f"{arguments['algorithm']} crashed the simulation{where}: killed by {name}")
    return 1


def _wait(child: subprocess.Popen[bytes]) -> int:
    """The child's exit status; Ctrl-C reaches the child too, and the parent waits for it."""
    while True:
        try:
            return child.wait()
        except KeyboardInterrupt:
            continue
