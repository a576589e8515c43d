"""The processes of the first-run compile: each compiles one part of the kernels.

Where it is safe (Linux, this process running no other thread), a compile process
is a fork of the run's own process, made once the run has imported NumPy, Numba and
the engine: it compiles at once, without importing them again (0.4 s of CPU a
process, which a first run on two cores shares with the compiles). Otherwise it is
a fresh interpreter. Either way it is killed by the kernel when the run dies, runs
at its part's priority, and ends without Python's teardown once its part is in
Numba's cache (releasing the LLVM objects one by one would add half a second that
the run waiting for it waits too: ``mimics`` itself ends so, ``leave.py``).
"""

from __future__ import annotations

import gc
import os
import signal
import subprocess
import sys
import threading
from typing import Protocol

from mimics.interfaces.child_processes import dying_with_parent

# the ray part yields the cores to the parts the run waits for; still is never waited for
NICE = {"ray": 5, "still": 19}
# a compile process's name in ps and top (at most 15 bytes: the kernel's limit)
NAME = "mimics-{part}"
_COMMAND = ("import os; {nice}from mimics.engine.compiling.warm_up import compile_part; "
            "compile_part({part!r}, helpers=False); os._exit(0)")
_PR_SET_PDEATHSIG, _PR_SET_NAME = 1, 15


class CompileProcess(Protocol):
    """What the run does with a compile process (``subprocess.Popen``'s names)."""

    part: str
    returncode: int | None

    def poll(self) -> int | None: ...

    def wait(self) -> int: ...

    def kill(self) -> None: ...


def start_compile(part: str) -> CompileProcess:
    """A process compiling ``part``: a fork when :func:`can_fork`, else a fresh interpreter."""
    return _Forked(part) if can_fork() else _spawn(part)


def can_fork() -> bool:
    """Whether a fork of this process may compile: Linux, and no other thread (a fork
    copies the locks other threads hold, such as Numba's compiler lock, held forever)."""
    from mimics.process_platform import has_death_signal

    return has_death_signal() and hasattr(os, "fork") and threading.active_count() == 1


def _spawn(part: str) -> CompileProcess:
    nice = f"os.nice({NICE[part]}); " if part in NICE and hasattr(os, "nice") else ""
    command = _COMMAND.format(nice=nice, part=part)
    process = subprocess.Popen(dying_with_parent([sys.executable, "-c", command]),
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    process.part = part  # type: ignore[attr-defined]
    return process  # type: ignore[return-value]


class _Forked:
    """A fork of this process compiling ``part``, waited for with ``os.waitpid``."""

    def __init__(self, part: str) -> None:
        self.part, self.returncode = part, None
        parent = os.getpid()
        self.pid = os.fork()
        if self.pid == 0:
            _compile_in_fork(part, parent)  # never returns

    def poll(self) -> int | None:
        if self.returncode is None:
            pid, status = os.waitpid(self.pid, os.WNOHANG)
            if pid:
                self.returncode = os.waitstatus_to_exitcode(status)
        return self.returncode

    def wait(self) -> int:
        if self.returncode is None:
            self.returncode = os.waitstatus_to_exitcode(os.waitpid(self.pid, 0)[1])
        return self.returncode

    def kill(self) -> None:
        if self.returncode is None:  # not reaped yet: the pid is still this child's
            os.kill(self.pid, signal.SIGKILL)


def _compile_in_fork(part: str, parent: int) -> None:
    """The fork's whole life: it never returns into the run's code, whatever happens."""
    code = 1
    try:
        # the run's objects, never freed here: no collection walks them (or copies their pages)
        gc.freeze()
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL)
        if os.getppid() != parent:  # the run died before the line above
            return
        libc.prctl(_PR_SET_NAME, NAME.format(part=part).encode()[:15])
        quiet = os.open(os.devnull, os.O_RDWR)
        for stream in (0, 1, 2):
            os.dup2(quiet, stream)
        os.nice(NICE.get(part, 0))
        from mimics.engine.compiling.warm_up import compile_part

        compile_part(part, helpers=False)  # the ray kernel's helpers are the run's
        code = 0
    finally:
        os._exit(code)
