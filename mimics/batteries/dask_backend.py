"""Running a battery's tasks on a Dask cluster (``dask.distributed``).

``mimics battery run FILE --dask tcp://scheduler:8786`` sends each run to the
cluster as one task, at most as many at a time as the cluster has threads.
The battery process stays the only writer of the database, so the database and
the results are the same as with local workers.

On each Dask worker a task does not run the simulation in the Dask worker
itself: it hands it to an isolated worker process of ours
(:class:`~mimics.batteries.workers.WorkerProcess`, kept alive between tasks,
one per Dask thread), so that a hang is killed at its timeout and a segfault
is recorded as ``crashed`` without taking the Dask worker down.

Run folders are written by the Dask workers at the battery folder's path: the
workers must see the battery folder (a shared file system), as they must see
the algorithm and scenario files.
"""

from __future__ import annotations

import contextlib
import os
import queue
import re
import tempfile
import threading
import time
import uuid
from pathlib import Path
from typing import Any

from mimics.batteries.tasks import Outcome, Task
from mimics.batteries.workers import WorkerProcess, allow_children
from mimics.world.errors import MimicsError

#: Seconds between two looks at how many threads the cluster has.
CAPACITY_REFRESH = 5.0
#: Seconds to reach the scheduler and see a worker, by default.
CONNECT_TIMEOUT = 30.0
#: A scheduler address: an optional protocol, an ASCII host name or IP, and a port.
ADDRESS = re.compile(r"((tcp|tls|ws|wss|ucx|inproc)://)?[A-Za-z0-9.\-_]+:[0-9]{1,5}"
                     r"|((tcp|tls|ws|wss|ucx)://)?\[[0-9A-Fa-f:.]+\]:[0-9]{1,5}")


class DaskExecutor:
    """Runs tasks on a Dask cluster, as many at once as it has threads.

    Args:
        address: the scheduler's address (``tcp://host:8786``).
        connect_timeout: seconds to reach the scheduler and see a worker
            (default :data:`CONNECT_TIMEOUT`).
        warm_up: each isolated worker loads the compiled kernels at start.

    Raises:
        MimicsError: when dask.distributed is not installed or the scheduler
            cannot be reached.
    """

    kind = "dask"

    def __init__(self, address: str, *, connect_timeout: float | None = None,
                 warm_up: bool = True) -> None:
        try:
            from distributed import Client
        except ImportError:
            raise MimicsError("--dask needs dask.distributed: pip install 'mimics-sim[cluster]'"
                              ) from None
        connect_timeout = CONNECT_TIMEOUT if connect_timeout is None else connect_timeout
        if not ADDRESS.fullmatch(address):
            # checked before Client(): a half-made Client hangs a minute at exit
            raise MimicsError(f"--dask {address!r}: expected a scheduler address like "
                              "tcp://host:8786")
        try:
            self.client = Client(address, timeout=connect_timeout, set_as_default=False)
        except (OSError, TimeoutError, ValueError) as exc:
            raise MimicsError(f"--dask {address}: cannot reach the scheduler: {exc}") from None
        try:
            self.client.wait_for_workers(1, timeout=connect_timeout)
        except (OSError, TimeoutError) as exc:
            self.client.close()
            raise MimicsError(f"--dask {address}: no worker joined the cluster: {exc}") from None
        self.warm_up = warm_up
        self._token = uuid.uuid4().hex[:8]
        self._done: queue.Queue[str] = queue.Queue()
        self._futures: dict[str, tuple[Any, Task]] = {}
        self._capacity = 1
        self._checked = -CAPACITY_REFRESH
        self._refresh()

    @property
    def capacity(self) -> int:
        """Threads of the cluster (looked up every few seconds)."""
        self._refresh()
        return self._capacity

    def free(self) -> int:
        """How many more tasks to send now."""
        return max(0, self.capacity - len(self._futures))

    def submit(self, task: Task) -> str:
        """Send a task to the cluster; returns ``"dask"`` (the worker is known at the end)."""
        key = f"mimics-run-{self._token}-{task.run_id}-{task.attempt}"
        future = self.client.submit(run_on_dask_worker, task, self.warm_up, key=key, pure=False)
        self._futures[key] = (future, task)
        future.add_done_callback(lambda f: self._done.put(f.key))
        return "dask"

    def poll(self, timeout: float) -> list[Outcome]:
        """Wait up to ``timeout`` seconds; returns the outcomes that came in."""
        keys: list[str] = []
        try:
            keys.append(self._done.get(timeout=timeout))
            while True:
                keys.append(self._done.get_nowait())
        except queue.Empty:
            pass
        outcomes = []
        for key in keys:
            entry = self._futures.pop(key, None)
            if entry is not None:
                outcomes.append(_outcome_of(*entry))
        return outcomes

    def close(self) -> None:
        """Cancel what is still queued and disconnect."""
        with contextlib.suppress(Exception):
            self.client.cancel([f for f, _ in self._futures.values()])
        self._futures.clear()
        with contextlib.suppress(Exception):
            self.client.close()

    def _refresh(self) -> None:
        now = time.monotonic()
        if now - self._checked < CAPACITY_REFRESH:
            return
        self._checked = now
        with contextlib.suppress(Exception):
            self._capacity = max(1, sum(self.client.nthreads().values()))


def _outcome_of(future: Any, task: Task) -> Outcome:
    if future.status == "finished":
        with contextlib.suppress(Exception):
            outcome = future.result()
            if isinstance(outcome, Outcome):
                return outcome
    try:
        error = future.exception() if future.status == "error" else None
        message = f"{type(error).__name__}: {error}" if error is not None else future.status
    except Exception as exc:  # a cancelled or lost future
        message = f"{type(exc).__name__}: {exc}"
    now = time.time()
    return Outcome(task.run_id, task.attempt, "crashed", error=f"the Dask task failed ({message})",
                   worker="dask", started=now, ended=now, wall_time=0.0)


# -- on the Dask workers ---------------------------------------------------------------

_POOL_LOCK = threading.Lock()
#: Idle isolated worker processes of this Dask worker process, by log folder.
#: Process infrastructure, not run state: each run starts from a fresh simulation.
_POOL: dict[str, list[WorkerProcess]] = {}
_SPAWNED = [0]


def run_on_dask_worker(task: Task, warm_up: bool = True) -> Outcome:
    """The Dask task: run ``task`` in an isolated worker process of this Dask worker."""
    log_dir = _log_dir(task.log_dir)
    with _POOL_LOCK:
        idle = _POOL.setdefault(str(log_dir), [])
        worker = None
        while idle and worker is None:
            candidate = idle.pop()
            worker = candidate if candidate.alive() else None
        if worker is None:
            _SPAWNED[0] += 1
            with allow_children():
                worker = WorkerProcess(f"dask-{os.getpid()}-{_SPAWNED[0]}", log_dir,
                                       death_signal=False, warm_up=warm_up, threads=1)
    outcome = worker.run(task)
    outcome.worker = f"{_dask_address()} {outcome.worker}".strip()
    if worker.alive() and not worker.busy:
        with _POOL_LOCK:
            _POOL[str(log_dir)].append(worker)
    else:
        worker.kill()
    return outcome


def _log_dir(wanted: str) -> Path:
    for folder in (Path(wanted) if wanted else None,
                   Path(tempfile.gettempdir()) / "mimics-workers"):
        if folder is None:
            continue
        with contextlib.suppress(OSError):
            folder.mkdir(parents=True, exist_ok=True)
            return folder
    return Path(tempfile.gettempdir())


def _dask_address() -> str:
    with contextlib.suppress(Exception):
        from distributed import get_worker

        return str(get_worker().address)
    return ""
