"""Each run of a battery under bubblewrap (``[battery] sandbox = "bwrap"``).

A run's process is ``bwrap ... python -m mimics.batteries.sandboxed_run``: a new
interpreter that imports the engine, loads the compiled kernels (read-only: see
:mod:`mimics.batteries.sandboxed_run`), reads one task from a socket, runs it and
sends the outcome back, as a worker of :mod:`mimics.batteries.workers` does. In
the sandbox:

* the whole file system is mounted read-only;
* the battery folder and the folders of the battery's algorithm files (and of the
  run's own file) are empty and read-only: a classmate's file cannot be read even
  by its absolute path, nor the battery's records written; three things are put
  back in them: the run's own copy of its file (read-only), its run folder (where it
  records, the one place it may write besides a scratch folder ``TMPDIR``) and the
  battery's scenario files (read-only);
* no network, no other process visible (new network and PID namespaces), a new
  session (no terminal to type into), and the process dies with the battery
  (``--die-with-parent``).

The battery process stays the only writer of the battery's records: it copies the
file in before, and after the run removes from the run folder whatever is neither
a file nor a folder (a link planted to make the battery write elsewhere).
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from dataclasses import replace
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

from mimics.batteries.isolation import Containment
from mimics.batteries.tasks import OUTCOME_FILE, Outcome, Task, hard_timeout
from mimics.batteries.workers import STARTUP_LIMIT, WorkerProcess
from mimics.world.errors import MimicsError

#: What the error says to install.
INSTALL = "apt-get install bubblewrap"
#: The options of every sandbox, before its folders.
BASE_OPTIONS = ("--ro-bind", "/", "/", "--dev", "/dev", "--proc", "/proc",
                "--tmpfs", "/dev/shm", "--unshare-all", "--die-with-parent", "--new-session")

#: Environment variables passed into the sandbox (by name, and by prefix).
KEPT_VARIABLES = frozenset({"PATH", "HOME", "LANG", "TZ", "VIRTUAL_ENV", "TERM"})
KEPT_PREFIXES = ("LC_", "PYTHON", "NUMBA_", "MIMICS_", "OMP_", "MKL_", "OPENBLAS_")


def bwrap_path() -> str | None:
    """Where ``bwrap`` is on ``PATH`` (None: not installed)."""
    return shutil.which("bwrap")


def require_bwrap(option: str = "sandbox = \"bwrap\"") -> str:
    """``bwrap``'s path, or one clear error naming the option and how to install it.

    Raises:
        MimicsError: ``bwrap`` is not on ``PATH``.
    """
    found = bwrap_path()
    if found is None:
        raise MimicsError(f"{option}: bubblewrap's `bwrap` is not installed (not on PATH); "
                          f"install it ({INSTALL} on Debian or Ubuntu) or drop the sandbox")
    return found


def check_sandbox(containment: Containment) -> None:
    """That ``bwrap`` is there, can make a sandbox here, and hides no part of Python.

    Raises:
        MimicsError: naming what is wrong; nothing is started.
    """
    bwrap = require_bwrap()
    for folder in containment.hidden:
        _check_hideable(folder)
    done = subprocess.run([bwrap, *BASE_OPTIONS, "true"], capture_output=True, text=True,
                          check=False)
    if done.returncode != 0:
        raise MimicsError("sandbox = \"bwrap\": bwrap cannot make a sandbox on this machine "
                          f"({done.stderr.strip() or f'exit status {done.returncode}'})")


def _check_hideable(folder: str) -> None:
    """A folder hidden from runs must not hold Python or mimics, which each run needs."""
    needed = {sys.prefix, sys.base_prefix, str(Path(sys.executable).resolve().parent),
              str(Path(__file__).resolve().parents[1])}
    for path in needed:
        if Path(path).resolve().is_relative_to(folder):
            raise MimicsError(f"sandbox = \"bwrap\": the folder {folder} (of the battery or "
                              f"of an algorithm file) would be hidden from each run, but it "
                              f"holds {path}, which runs need; keep submissions and batteries "
                              "in folders of their own")


def sandbox_command(bwrap: str, containment: Containment, task: Task, box: Path,
                    info_fd: int, task_fd: int, threads: int, label: str) -> list[str]:
    """The ``bwrap`` command line of one run (``box``: its private folder)."""
    hidden = set(containment.hidden)
    if task.algorithm.endswith(".py"):
        hidden.add(str(Path(task.algorithm).resolve().parent))
    for folder in hidden:
        _check_hideable(folder)
    outermost = sorted(f for f in hidden
                       if not any(f != o and Path(f).is_relative_to(o) for o in hidden))
    command = [bwrap, *BASE_OPTIONS]
    for folder in outermost:
        command += ["--tmpfs", folder]
    for file in containment.visible:
        if Path(file).is_file():
            command += ["--ro-bind", file, file]
    # the battery's working folder, so that files are named in errors as outside
    cwd = os.getcwd()
    if any(Path(cwd).is_relative_to(folder) and cwd != folder for folder in outermost):
        command += ["--dir", cwd]  # (empty) inside a hidden folder
    command += ["--ro-bind", str(box / "src"), str(box / "src"),
                "--bind", str(box / "tmp"), str(box / "tmp"),
                "--bind", task.folder, task.folder,
                "--chdir", cwd, "--info-fd", str(info_fd)]
    for folder in outermost:  # after the binds into them: writing there fails too
        command += ["--remount-ro", folder]
    return [*command, sys.executable, "-m", "mimics.batteries.sandboxed_run", str(task_fd),
            str(threads), label]


def sandbox_environment() -> dict[str, str]:
    """The battery's environment variables a run needs (Python's, Numba's, mimics', the
    locale, thread counts), without the rest: a teacher's tokens stay out of the sandbox."""
    return {name: value for name, value in os.environ.items()
            if name in KEPT_VARIABLES or name.startswith(KEPT_PREFIXES)}


class _Started:
    """A sandbox's ``bwrap`` process as :class:`WorkerProcess` reads its process."""

    def __init__(self, popen: subprocess.Popen[bytes] | None) -> None:
        self.popen = popen
        self.pid = popen.pid if popen is not None else None
        # a pidfd: readable when the process ends, as a multiprocessing sentinel is
        self.sentinel = os.pidfd_open(popen.pid) if popen is not None else -1

    @property
    def exitcode(self) -> int | None:
        """The exit status, a signal's as ``-N`` (bwrap exits 128 + N for its command's)."""
        if self.popen is None:
            return None
        code = self.popen.poll()
        if code is not None and 128 < code < 128 + signal.NSIG:
            return 128 - code
        return code

    def is_alive(self) -> bool:
        return self.popen is not None and self.popen.poll() is None

    def join(self, timeout: float | None = None) -> None:
        if self.popen is not None:
            with contextlib.suppress(subprocess.TimeoutExpired):
                self.popen.wait(timeout)

    def terminate(self) -> None:
        if self.is_alive():
            assert self.popen is not None
            with contextlib.suppress(ProcessLookupError):
                self.popen.terminate()

    def kill(self) -> None:
        if self.is_alive():
            assert self.popen is not None
            with contextlib.suppress(ProcessLookupError):
                self.popen.kill()

    def close(self) -> None:
        if self.sentinel >= 0:
            with contextlib.suppress(OSError):
                os.close(self.sentinel)
            self.sentinel = -1


class SandboxedWorker(WorkerProcess):
    """A slot that runs each task it is sent in a new sandboxed process (then ends).

    It is ready at once; :meth:`send` starts the sandbox. The run's hard deadline
    starts when the sandbox has imported the engine and says it is ready.
    """

    def __init__(self, name: str, log_dir: Path | None, containment: Containment, *,
                 threads: int = 1) -> None:
        self.name = name
        self.containment = containment
        self.threads = threads
        if log_dir is not None:
            log_dir.mkdir(parents=True, exist_ok=True)
        self.log_path = (log_dir / f"{name}.log").resolve() if log_dir is not None else None
        self.process: Any = _Started(None)
        self.conn: Any = None
        self.ready = True
        self.started = time.monotonic()
        self.task: Task | None = None
        self.deadline = float("inf")
        self.sent_at = 0.0
        self._log_offset = 0
        self._box: Path | None = None
        self._info = -1
        self._child_pid: int | None = None

    def waitables(self) -> list[Any]:
        return [self.conn, self.process.sentinel] if self.conn is not None else []

    def send(self, task: Task) -> None:
        """Start the sandbox for ``task`` and hand it the task."""
        bwrap = require_bwrap()
        box = Path(f"{task.folder}.box")
        (box / "src").mkdir(parents=True)
        (box / "tmp").mkdir()
        Path(task.folder).mkdir(parents=True, exist_ok=True)
        source = ""
        if task.algorithm.endswith(".py") and Path(task.algorithm).is_file():
            source = str(box / "src" / Path(task.algorithm).name)
            shutil.copyfile(task.algorithm, source)
        ours, theirs = socket.socketpair()
        info_read, info_write = os.pipe()
        self._log_offset = _size(self.log_path)
        log = open(self.log_path, "ab") if self.log_path else None  # noqa: SIM115
        try:
            command = sandbox_command(bwrap, self.containment, task, box, info_write,
                                      theirs.fileno(), self.threads, self.name)
            env = {**sandbox_environment(), "PYTHONUNBUFFERED": "1", "TMPDIR": str(box / "tmp")}
            popen = subprocess.Popen(command, stdin=subprocess.DEVNULL, stdout=log,
                                     stderr=subprocess.STDOUT if log else None, env=env,
                                     pass_fds=(theirs.fileno(), info_write),
                                     start_new_session=True)  # Ctrl-C is the battery's
        finally:
            theirs.close()
            os.close(info_write)
            if log is not None:
                log.close()
        self._box, self._info = box, info_read
        self.process = _Started(popen)
        self.conn = Connection(ours.detach())
        self.task = task
        self.sent_at = time.monotonic()
        self.deadline = self.sent_at + STARTUP_LIMIT + hard_timeout(task.timeout)
        self.conn.send(replace(task, source=source))  # waits in the socket until read

    def receive(self) -> Outcome | None:
        kind, payload = self.conn.recv()
        if kind == "ready":  # imports done: the run's own time starts now
            if self.task is not None:
                self.sent_at = time.monotonic()
                self.deadline = self.sent_at + hard_timeout(self.task.timeout)
            return None
        if self.task is not None:
            keep_only_files(Path(self.task.folder))
        self.task = None
        self.deadline = float("inf")
        payload.worker = self.label  # with bwrap's pid, which the sandbox cannot see
        return payload

    @property
    def label(self) -> str:
        return f"{self.name} (bwrap pid {self.process.pid})"

    def failure(self, state: str) -> Outcome:
        if self.task is not None:
            keep_only_files(Path(self.task.folder))
        return super().failure(state)

    def dump_and_kill(self) -> None:
        """Ask the sandboxed Python for a stack dump (into the log), then kill it."""
        pid = self._sandboxed_pid()
        if pid is not None and self.alive():
            with contextlib.suppress(OSError):
                os.kill(pid, signal.SIGUSR1)
                self.process.join(0.3)
        self.kill()

    def kill(self) -> None:
        self.process.terminate()
        self.process.join(1.0)
        self.process.kill()
        self.process.join(2.0)
        self.process.close()
        if self.conn is not None:
            self.conn.close()
            self.conn = None
        if self._info >= 0:
            os.close(self._info)
            self._info = -1
        if self._box is not None:
            shutil.rmtree(self._box, ignore_errors=True)
            self._box = None

    def stop(self, wait: float = 2.0) -> None:
        self.process.join(0.0 if self.busy else wait)
        self.kill()

    def _sandboxed_pid(self) -> int | None:
        """The sandboxed Python's pid outside its PID namespace: the child of the
        namespace's first process, whose pid bwrap writes to ``--info-fd``."""
        if self._child_pid is None and self._info >= 0:
            os.set_blocking(self._info, False)
            with contextlib.suppress(OSError, ValueError, KeyError, TypeError):
                init = int(json.loads(os.read(self._info, 4096))["child-pid"])
                with open(f"/proc/{init}/task/{init}/children") as f:
                    self._child_pid = int(f.read().split()[0])
        return self._child_pid


def keep_only_files(folder: Path) -> None:
    """Remove from a run folder whatever is neither a regular file nor a folder.

    A sandboxed run writes its own folder; a link it left there (to a classmate's
    file, or to where the battery would then write) or a pipe would be followed by
    the battery process, which is outside the sandbox.
    """
    if not folder.is_dir() or folder.is_symlink():
        return
    outcome = folder / OUTCOME_FILE  # the battery writes it: whatever the run left goes
    if outcome.is_dir() and not outcome.is_symlink():
        shutil.rmtree(outcome, ignore_errors=True)
    for root, folders, files in os.walk(folder):
        for name in [*folders, *files]:
            path = Path(root) / name
            if path.is_symlink() or not (path.is_file() or path.is_dir()):
                with contextlib.suppress(OSError):
                    path.unlink()
        folders[:] = [f for f in folders if (Path(root) / f).is_dir()
                      and not (Path(root) / f).is_symlink()]


def _size(path: Path | None) -> int:
    try:
        return path.stat().st_size if path is not None else 0
    except OSError:
        return 0
