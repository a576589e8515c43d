"""Isolated, long-lived worker processes that run a battery's simulations.

Workers come from the ``forkserver`` context where the platform has it (Linux,
macOS), else from ``spawn``. The fork server is a fresh interpreter that
imports the engine once (it preloads :mod:`mimics.batteries.preload`); each
worker is forked from it with everything imported, loads the compiled Numba
kernels with a tiny warm-up run, and then runs tasks sent over a pipe until
told to stop, so that imports and kernels are loaded once per worker, not per
run, and replacing a dead worker is cheap (what the cache lacks is compiled once
before: :mod:`mimics.batteries.compile_once`). Under ``isolation = "run"`` a worker
runs one task and exits (:mod:`mimics.batteries.isolation`). Each worker runs Numba's
parallel kernels on ``threads`` threads. The parent keeps the other end of the
pipe (:class:`WorkerProcess`):

* an exception in user code comes back as an outcome (see
  :func:`mimics.batteries.tasks.execute`) and the worker goes on;
* a run past its wall-clock limit that does not stop by itself: the parent
  asks the worker for a stack dump (``SIGUSR1``, written to the worker's log),
  kills it and records ``timeout``;
* a worker that dies (a segfault in a C extension, ``os._exit``, the
  out-of-memory killer): the parent records ``crashed`` with the exit code and
  the end of the worker's log (Python's fault handler writes the stack of a
  fatal signal there), and starts a replacement.

A worker dies with the battery process, even one killed by ``SIGKILL``: on
Linux by ``PR_SET_PDEATHSIG`` (the fork server exits with the battery), and
everywhere by a thread that watches its parent.
Worker stdout and stderr (user ``print`` calls included) go to
``workers/NAME.log`` in the battery folder, not to the terminal. Submissions are
imported only here, never in the battery process, each run in a fresh empty
working folder, under an audit hook that refuses user code ``gc`` and frames
(:mod:`mimics.engine.user_code.guard`).
"""

from __future__ import annotations

import contextlib
import faulthandler
import math
import multiprocessing
import multiprocessing.connection
import os
import shutil
import signal
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

from mimics.batteries.tasks import Outcome, Task, execute, hard_timeout

#: Seconds a new worker may take to import mimics and warm up before it is given up on.
STARTUP_LIMIT = 180.0
#: Bytes of a worker's log kept in a failed run's traceback.
LOG_TAIL = 6000
#: Start of the line a worker writes to its log before each run.
RUN_MARK = "--- mimics battery:"


# -- inside the worker -----------------------------------------------------------

def worker_main(conn: Any, parent_pid: int, log_path: str, death_signal: bool,
                warm_up: bool, threads: int, one_task: bool = False, label: str = "") -> None:
    """The worker loop: receive a :class:`Task`, send back its :class:`Outcome`.

    A ``None`` message or a closed pipe ends the loop; so does the first outcome
    when ``one_task`` (``isolation = "run"``: no run sees what another left behind).
    """
    if death_signal:
        _die_with_parent_signal()
    threading.Thread(target=_watch_parent, args=(os.getppid(), parent_pid), daemon=True).start()
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is for the parent
    if log_path:
        _redirect_output(log_path)
    faulthandler.enable(all_threads=True)
    if hasattr(faulthandler, "register") and hasattr(signal, "SIGUSR1"):
        faulthandler.register(signal.SIGUSR1, all_threads=True)
    _limit_threads(threads)
    if warm_up:
        warm_up_engine()
    from mimics.engine.user_code import install_guard

    install_guard()  # after the warm-up: user code may not walk gc or frames to the world
    label = label or f"{multiprocessing.current_process().name} (pid {os.getpid()})"
    with contextlib.suppress(BrokenPipeError, EOFError, OSError):
        conn.send(("ready", os.getpid()))
        while True:
            task = conn.recv()
            if task is None:
                break
            if log_path:
                print(f"{RUN_MARK} run {task.run_id} attempt {task.attempt} ---", flush=True)
            conn.send(("outcome", execute(task, label)))
            if one_task:
                break
    conn.close()


def _die_with_parent_signal() -> None:
    """Linux: have the kernel kill this process when its parent dies."""
    from mimics.process_platform import has_death_signal

    if not has_death_signal():
        return
    with contextlib.suppress(Exception):
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, int(signal.SIGKILL))  # PR_SET_PDEATHSIG


def _watch_parent(parent: int, battery: int) -> None:
    """Exit when the parent (the battery, or the fork server) or the battery is gone."""
    while True:
        time.sleep(0.5)
        if os.getppid() != parent:
            os._exit(0)
        if battery != parent:
            try:
                os.kill(battery, 0)
            except ProcessLookupError:
                os._exit(0)
            except OSError:
                pass


def _redirect_output(path: str) -> None:
    sys.stdout.flush()
    sys.stderr.flush()
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
    os.dup2(fd, 1)
    os.dup2(fd, 2)
    os.close(fd)
    for stream in (sys.stdout, sys.stderr):
        with contextlib.suppress(AttributeError, ValueError):
            stream.reconfigure(line_buffering=True)  # type: ignore[union-attr]


def _limit_threads(threads: int) -> None:
    """Start Numba's thread pool with ``threads`` threads.

    Numba guards the start of its pool with a multiprocessing ``RLock`` when the
    start method's name holds "fork". Under ``forkserver`` that lock is a named
    semaphore registered with the battery's resource tracker, which a worker
    killed for time or crashed never releases: the battery then ended with
    "resource_tracker: There appear to be N leaked semaphore objects". Under
    ``fork`` the same lock is unlinked as soon as it is made, so it is made there.
    """
    with contextlib.suppress(Exception):
        import numba

        method = multiprocessing.get_start_method(allow_none=True)
        forks = "fork" in multiprocessing.get_all_start_methods()
        if forks:
            multiprocessing.set_start_method("fork", force=True)
        try:
            numba.set_num_threads(max(1, min(threads, numba.config.NUMBA_NUM_THREADS)))
        finally:
            if forks:
                multiprocessing.set_start_method(method, force=True)


def warm_up_engine() -> None:
    """Import the engine and load the compiled kernels with a tiny recorded run."""
    from mimics.records.runner import prepare, run_to_folder

    folder = tempfile.mkdtemp(prefix="mimics-warm-up-")
    try:
        run_to_folder(prepare("line", "go_to_goal", robots=2, time=0.3, seed=0), folder,
                      robot_logs="off")
    except Exception:  # warming up only saves time; the runs report errors
        pass
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def worker_context(warm_up: bool = True) -> multiprocessing.context.BaseContext:
    """The ``forkserver`` context preloading the engine where available, else ``spawn``."""
    from mimics.process_platform import worker_start_method

    if worker_start_method() == "spawn":
        return multiprocessing.get_context("spawn")
    context = multiprocessing.get_context("forkserver")
    if warm_up:
        context.set_forkserver_preload(["mimics.batteries.preload"])
    return context


# -- in the parent ---------------------------------------------------------------

@contextlib.contextmanager
def allow_children() -> Any:
    """Let a daemonic process (a Dask worker) start worker processes.

    ``multiprocessing`` refuses children to daemonic processes so that they
    are not orphaned; ours watch their parent and exit with it.
    """
    config = multiprocessing.current_process()._config  # type: ignore[attr-defined]
    was = config.get("daemon")
    config["daemon"] = False
    try:
        yield
    finally:
        if was is not None:
            config["daemon"] = was


class WorkerProcess:
    """A worker process seen from the parent: its pipe, its current task, its deadline.

    Args:
        name: a short name (``w1``), also the name of its log file.
        log_dir: folder of the worker's log (None: output goes where the parent's goes).
        death_signal: use ``PR_SET_PDEATHSIG`` (only when created from a thread
            that lives as long as the worker, as the battery's main thread, or
            from the fork server).
        warm_up: load the compiled kernels with a tiny run before the first task.
        threads: threads of Numba's parallel kernels in this worker.
        one_task: the worker exits after its first run (``isolation = "run"``).
    """

    def __init__(self, name: str, log_dir: Path | None, *, death_signal: bool = True,
                 warm_up: bool = True, threads: int = 1, one_task: bool = False) -> None:
        context = worker_context(warm_up)
        forked = context.get_start_method() == "forkserver"
        self.name = name
        if log_dir is not None:  # the worker opens its log at once: a fast fork may beat
            log_dir.mkdir(parents=True, exist_ok=True)  # the driver's mkdir
        self.log_path = (log_dir / f"{name}.log").resolve() if log_dir is not None else None
        parent_end, child_end = context.Pipe()
        self.process = context.Process(
            target=worker_main, name=name, daemon=False,
            args=(child_end, os.getpid(), str(self.log_path or ""), death_signal or forked,
                  warm_up, threads, one_task))
        self.process.start()
        child_end.close()
        self.conn = parent_end
        self.ready = False
        self.started = time.monotonic()
        self.task: Task | None = None
        self.deadline = math.inf
        self.sent_at = 0.0  # when the current task was sent (monotonic)
        self._log_offset = 0

    @property
    def label(self) -> str:
        """``"w1 (pid 1234)"``."""
        return f"{self.name} (pid {self.process.pid})"

    @property
    def busy(self) -> bool:
        """Whether a task was sent and its outcome has not come back."""
        return self.task is not None

    def waitables(self) -> list[Any]:
        """The pipe and the process sentinel, for ``multiprocessing.connection.wait``."""
        return [self.conn, self.process.sentinel]

    def send(self, task: Task) -> None:
        """Give the worker a task; its hard deadline starts now."""
        self._log_offset = _size(self.log_path)
        self.task = task
        self.sent_at = time.monotonic()
        self.deadline = self.sent_at + hard_timeout(task.timeout)
        self.conn.send(task)

    def receive(self) -> Outcome | None:
        """Read one message: the outcome of the current task, or None (the ready signal).

        Raises:
            EOFError: the worker is gone.
        """
        kind, payload = self.conn.recv()
        if kind == "ready":
            self.ready = True
            return None
        self.task = None
        self.deadline = math.inf
        return payload

    def alive(self) -> bool:
        """Whether the process is still running."""
        return self.process.is_alive()

    def failure(self, state: str) -> Outcome:
        """The outcome of the current task when the worker died or was killed for time."""
        task = self.task
        assert task is not None
        now = time.time()
        elapsed = time.monotonic() - self.sent_at
        if state == "timeout":
            error = (f"wall-clock timeout: no result after {elapsed:.1f} s (limit "
                     f"{task.timeout:g} s); the worker process was killed")
        else:
            error = f"the worker process died during the run ({describe_exit(self.process)})"
        outcome = Outcome(task.run_id, task.attempt, state, error=error,
                          traceback=self.log_tail(), worker=self.label,
                          started=now - elapsed, ended=now, wall_time=elapsed)
        self.task = None
        self.deadline = math.inf
        return outcome

    def log_tail(self) -> str:
        """What the worker wrote to its log since the current task was sent (the end of it)."""
        if self.log_path is None:
            return ""
        try:
            with open(self.log_path, "rb") as f:
                f.seek(max(self._log_offset, _size(self.log_path) - LOG_TAIL))
                text = f.read().decode("utf-8", "replace")
        except OSError:
            return ""
        lines = [line for line in text.splitlines() if not line.startswith(RUN_MARK)]
        text = "\n".join(lines)
        return text.split("\nExtension modules:")[0].strip()  # the fault handler's module list

    def dump_and_kill(self) -> None:
        """Ask for a stack dump in the log (a hung run), then kill the process."""
        if self.alive() and hasattr(signal, "SIGUSR1") and self.process.pid:
            with contextlib.suppress(OSError):
                os.kill(self.process.pid, signal.SIGUSR1)
                self.process.join(0.3)
        self.kill()

    def kill(self) -> None:
        """Terminate the process (SIGTERM, then SIGKILL) and close the pipe."""
        if self.alive():
            self.process.terminate()
            self.process.join(1.0)
        if self.alive():
            self.process.kill()
            self.process.join(2.0)
        self.conn.close()

    def stop(self, wait: float = 2.0) -> None:
        """Ask an idle worker to exit; kill it if it does not within ``wait`` seconds."""
        with contextlib.suppress(OSError, ValueError):
            if not self.busy:
                self.conn.send(None)
        self.process.join(wait if not self.busy else 0.0)
        self.kill()

    def run(self, task: Task) -> Outcome:
        """Run one task to its end, blocking (waiting for the worker to be ready first).

        Used on Dask workers, one task per thread. Returns the run's outcome,
        or a ``timeout``/``crashed`` one (the worker is then dead; check
        :meth:`alive` before reusing it).
        """
        while not self.ready:
            remaining = self.started + STARTUP_LIMIT - time.monotonic()
            if remaining <= 0 or not self._wait_ready(remaining):
                self.task = task
                self.sent_at = time.monotonic()
                self.kill()
                outcome = self.failure("crashed")
                outcome.error = f"the worker process could not start ({outcome.error})"
                return outcome
        self.send(task)
        while True:
            remaining = self.deadline - time.monotonic()
            if remaining <= 0:
                self.dump_and_kill()
                return self.failure("timeout")
            ready = multiprocessing.connection.wait(self.waitables(), timeout=remaining)
            if self.conn in ready:
                try:
                    outcome = self.receive()
                except (EOFError, OSError):
                    self.process.join(1.0)
                    return self.failure("crashed")
                if outcome is not None:
                    return outcome
            elif ready:
                self.process.join(1.0)
                return self.failure("crashed")

    def _wait_ready(self, limit: float) -> bool:
        ready = multiprocessing.connection.wait(self.waitables(), timeout=limit)
        if self.conn in ready:
            try:
                self.receive()
            except (EOFError, OSError):
                return False
            return True
        return False


def describe_exit(process: multiprocessing.process.BaseProcess) -> str:
    """``"exit code 3"``, ``"killed by signal SIGSEGV"`` and the like."""
    code = process.exitcode
    if code is None:
        return "still running"
    if code < 0:
        try:
            name = signal.Signals(-code).name
        except ValueError:
            name = str(-code)
        hint = " (out of memory?)" if name == "SIGKILL" else ""
        return f"killed by signal {name}{hint}"
    return f"exit code {code}"


def _size(path: Path | None) -> int:
    if path is None:
        return 0
    try:
        return path.stat().st_size
    except OSError:
        return 0
