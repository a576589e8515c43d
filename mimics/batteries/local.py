"""Running a battery's tasks on local worker processes.

:class:`LocalExecutor` keeps ``workers`` :class:`~mimics.batteries.workers.WorkerProcess`
alive, gives a task to each idle one, and turns what happens into outcomes:
the run's own outcome, ``timeout`` (killed past its hard deadline) or
``crashed`` (the process died). A killed or dead worker is replaced at once;
the battery goes on. Under ``isolation = "run"`` every worker runs one run and
is replaced (a fresh fork of the fork server); under ``sandbox = "bwrap"`` each
run is a process of its own under bubblewrap (:mod:`mimics.batteries.sandbox`).
"""

from __future__ import annotations

import contextlib
import multiprocessing.connection
import os
import time
from pathlib import Path

from mimics.batteries.compile_once import compile_missing_parts
from mimics.batteries.isolation import Containment
from mimics.batteries.tasks import Outcome, Task
from mimics.batteries.workers import STARTUP_LIMIT, WorkerProcess
from mimics.world.errors import MimicsError

#: Workers that die before getting ready, in a row, before the battery gives up.
MAX_STARTUP_FAILURES = 3


class LocalExecutor:
    """A pool of isolated worker processes on this machine.

    Each worker runs Numba's parallel kernels on ``cpu_count // workers``
    threads (one with the default, one worker per core).

    Args:
        workers: how many processes run simulations at once.
        log_dir: folder of the workers' logs.
        warm_up: each worker loads the compiled kernels with a tiny run at start;
            before the workers start, what Numba's cache lacks is compiled once
            (:mod:`mimics.batteries.compile_once`), not once per worker.
        containment: a process per run, a sandbox (:mod:`mimics.batteries.isolation`).

    Raises:
        MimicsError: a sandbox is asked and ``bwrap`` is missing or cannot run here;
            no worker is started.
    """

    kind = "local"

    def __init__(self, workers: int, log_dir: Path | None = None, *, warm_up: bool = True,
                 containment: Containment | None = None) -> None:
        if workers < 1:
            raise MimicsError(f"--workers: expected a whole number >= 1, got {workers}")
        self.containment = containment or Containment()
        if self.containment.sandbox:
            from mimics.batteries.sandbox import check_sandbox

            check_sandbox(self.containment)
        self.log_dir = log_dir
        self.warm_up = warm_up
        self.threads = max(1, (os.cpu_count() or 1) // workers)
        self._spawned = 0
        self._startup_failures = 0
        if warm_up:
            compile_missing_parts(log_dir)
        self._slots = [self._spawn(slot) for slot in range(workers)]

    @property
    def capacity(self) -> int:
        """How many runs can go at once."""
        return len(self._slots)

    def free(self) -> int:
        """Workers ready and idle: how many tasks :meth:`submit` takes now."""
        return sum(1 for w in self._slots if w.ready and not w.busy)

    def submit(self, task: Task) -> str:
        """Send a task to an idle worker; returns the worker's label."""
        worker = next(w for w in self._slots if w.ready and not w.busy)
        worker.send(task)
        return worker.label

    def poll(self, timeout: float) -> list[Outcome]:
        """Wait up to ``timeout`` seconds; returns the outcomes that came in.

        Raises:
            MimicsError: when new workers keep dying before they are ready.
        """
        nearest = min((w.deadline for w in self._slots), default=float("inf"))
        wait = max(0.0, min(timeout, nearest - time.monotonic()))
        waitables = [x for w in self._slots for x in w.waitables()]
        ready = set(multiprocessing.connection.wait(waitables, timeout=wait))
        outcomes: list[Outcome] = []
        for index, worker in enumerate(self._slots):
            gone = finished = False
            if worker.conn in ready or worker.process.sentinel in ready:
                try:  # every message: a fast run's "ready" and outcome may come at once
                    while worker.conn.poll():
                        outcome = worker.receive()
                        if outcome is not None:
                            outcomes.append(outcome)
                            finished = True
                except (EOFError, OSError):
                    gone = True
                if worker.ready:
                    self._startup_failures = 0
                if finished and self.containment.one_run_per_process:  # it ends: a fresh one
                    worker.process.join(0.5)
                    self._replace(index)
                    continue
            if gone or worker.process.sentinel in ready:
                worker.process.join(1.0)
                if not worker.alive():
                    if worker.busy:
                        outcomes.append(worker.failure("crashed"))
                    elif not worker.ready:
                        self._startup_failed(worker)
                    self._replace(index)
                    continue
            if worker.busy and time.monotonic() >= worker.deadline:
                worker.dump_and_kill()
                outcomes.append(worker.failure("timeout"))
                self._replace(index)
            elif not worker.ready and time.monotonic() - worker.started > STARTUP_LIMIT:
                self._startup_failed(worker)
                self._replace(index)
        return outcomes

    def close(self) -> None:
        """Stop every worker (idle ones cleanly, busy ones killed)."""
        for worker in self._slots:
            if not worker.ready:  # still starting: it has run nothing to finish
                worker.kill()
                continue
            with contextlib.suppress(OSError, ValueError):
                if not worker.busy and worker.alive():
                    worker.conn.send(None)
        deadline = time.monotonic() + 2.0
        for worker in self._slots:
            if not worker.busy:
                worker.process.join(max(0.0, deadline - time.monotonic()))
            worker.kill()
        self._slots = []

    def _spawn(self, slot: int) -> WorkerProcess:
        self._spawned += 1
        # a process per run: one log per slot (workers/w1.log...), not one per run
        number = slot + 1 if self.containment.one_run_per_process else self._spawned
        if self.containment.sandbox:
            from mimics.batteries.sandbox import SandboxedWorker

            return SandboxedWorker(f"s{number}", self.log_dir, self.containment,
                                   threads=self.threads)
        return WorkerProcess(f"w{number}", self.log_dir, death_signal=True,
                             warm_up=self.warm_up, threads=self.threads,
                             one_task=self.containment.one_run_per_process)

    def _replace(self, index: int) -> None:
        self._slots[index].kill()
        self._slots[index] = self._spawn(index)

    def _startup_failed(self, worker: WorkerProcess) -> None:
        self._startup_failures += 1
        if self._startup_failures >= MAX_STARTUP_FAILURES:
            tail = worker.log_tail().splitlines()[-1:] or ["no output"]
            raise MimicsError(f"worker processes die before they are ready ({tail[0]}); see "
                              f"{worker.log_path or 'their output'}")
