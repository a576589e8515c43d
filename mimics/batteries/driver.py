"""Running a battery: create it, resume it, re-run its failures.

The battery process is the only writer of the database. It holds a lock on
``battery.lock`` while it runs (a second battery on the same folder is refused;
the lock goes with the process, even one killed by SIGKILL). For each run it
commits ``running``, hands the task to a worker, and when the outcome comes
back writes it into the run's folder (``battery.json``), renames the folder
from ``tmp/`` to ``runs/`` and commits the final state. A folder under
``runs/`` is therefore always complete, and a resumed battery neither loses
nor repeats a finished run.

Battery folder::

    batteries/night1/
      battery.db       the state of every run (see store.py)
      battery.toml     a copy of the battery file
      battery.lock     held by the running battery process
      runs/00001-go_to_goal-line-robots=1-s1/   one folder per run (summary.json, ...)
      tmp/             runs being written (cleared when a battery starts)
      workers/w1.log   the workers' output (user prints, fault dumps)

>>> import tempfile
>>> from mimics.batteries.spec import spec_from_dict
>>> spec = spec_from_dict({"battery": {"algorithms": ["go_to_goal"], "seeds": 2, "time": 1.0},
...                        "scenarios": [{"name": "line", "robots": 2}]})
>>> result = run_battery(spec, tempfile.mkdtemp() + "/b", workers=1, progress=False)
>>> result.counts
{'done': 2}
"""

from __future__ import annotations

import contextlib
import os
import shutil
import signal
import threading
import time
import uuid
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Protocol

from mimics.batteries.isolation import containment_of, refuse_dask
from mimics.batteries.progress import BatteryProgress
from mimics.batteries.rounds import Rounds, extend_all
from mimics.batteries.spec import BatterySpec, load_battery
from mimics.batteries.store import RUNS_DIR, TMP_DIR, WORKERS_DIR, BatteryStore
from mimics.batteries.tasks import FAILED_STATES, OUTCOME_FILE, Outcome, Task
from mimics.world.errors import MimicsError

LOCK_NAME = "battery.lock"

try:
    import fcntl
except ImportError:  # Windows
    fcntl = None  # type: ignore[assignment]


class Executor(Protocol):
    """Where runs go: :class:`~mimics.batteries.local.LocalExecutor` or
    :class:`~mimics.batteries.dask_backend.DaskExecutor`."""

    def free(self) -> int:
        """How many more tasks to submit now."""

    def submit(self, task: Task) -> str:
        """Start a task; returns a label of where it runs."""

    def poll(self, timeout: float) -> list[Outcome]:
        """Wait up to ``timeout`` seconds for outcomes (runs, timeouts, crashes)."""

    def close(self) -> None:
        """Stop everything (may be called more than once)."""


@dataclass(frozen=True)
class BatteryResult:
    """What a battery session left: runs by state, and what this session did.

    Attributes:
        folder: the battery folder.
        counts: runs by state at the end of the session.
        finished: runs that finished in this session.
        adopted: runs found finished at resume (the battery had died just after them).
        elapsed: wall-clock seconds of the session.
    """

    folder: Path
    counts: dict[str, int]
    finished: int
    adopted: int
    elapsed: float

    def line(self) -> str:
        """One line for the terminal: ``"12 runs: 10 done, 2 error in 3.1 s"``."""
        total = sum(self.counts.values())
        parts = ", ".join(f"{n} {state}" for state, n in self.counts.items())
        return f"{self.folder}: {total} runs: {parts} ({self.finished} run in {self.elapsed:.1f} s)"


def run_battery(spec: BatterySpec | str | Path, out: str | Path, *, workers: int | None = None,
                dask: str | None = None, progress: bool | None = None) -> BatteryResult:
    """Create a battery folder listing every run, then run them all.

    Args:
        spec: a validated spec or the path of a battery file.
        out: the battery folder (new or empty).
        workers: local worker processes (default: ``os.cpu_count()``).
        dask: a Dask scheduler address (``tcp://host:8786``) instead of local workers.
        progress: show a progress bar (None: when stderr is a terminal).

    Raises:
        MimicsError: a bad battery file, or a folder that already holds a battery;
            nothing is started.
    """
    if not isinstance(spec, BatterySpec):
        spec = load_battery(spec)
    _check_workers(workers)
    BatteryStore.check_free(out)
    cluster = None
    if dask:  # reach the cluster before anything is written
        from mimics.batteries.dask_backend import DaskExecutor

        refuse_dask(spec)
        cluster = DaskExecutor(dask)
    try:
        store = BatteryStore.create(out, spec)
    except BaseException:
        if cluster is not None:
            cluster.close()
        raise
    try:
        if spec.source and Path(spec.source).is_file():
            shutil.copyfile(spec.source, store.folder / "battery.toml")
        return _drive(store, workers=workers, dask=dask, progress=progress, executor=cluster)
    finally:
        store.close()


def resume_battery(folder: str | Path, *, workers: int | None = None, dask: str | None = None,
                   progress: bool | None = None) -> BatteryResult:
    """Go on with a battery where it stopped (after a kill, a reboot, a crash).

    Runs left ``running`` by a dead battery go back to ``pending`` (or are
    adopted when their folder shows they had finished); finished runs are
    kept, and the pending ones run.
    """
    _check_workers(workers)
    store = BatteryStore.open(folder)
    try:
        return _drive(store, workers=workers, dask=dask, progress=progress)
    finally:
        store.close()


def rerun_failed(folder: str | Path, *, states: tuple[str, ...] = FAILED_STATES,
                 workers: int | None = None, dask: str | None = None,
                 progress: bool | None = None) -> BatteryResult:
    """Run again the runs of a battery that failed (``error``, ``timeout``, ``crashed``).

    They run with the same seeds; their new outcome replaces the old one
    (and their attempts count goes up).
    """
    _check_workers(workers)
    store = BatteryStore.open(folder)
    try:
        return _drive(store, workers=workers, dask=dask, progress=progress, reset=states)
    finally:
        store.close()


def _check_workers(workers: int | None) -> None:
    if workers is not None and (isinstance(workers, bool) or workers < 1):
        raise MimicsError(f"--workers: expected a whole number >= 1, got {workers}")


# -- the loop ------------------------------------------------------------------------

def _drive(store: BatteryStore, *, workers: int | None, dask: str | None,
           progress: bool | None, reset: tuple[str, ...] = (),
           executor: Executor | None = None) -> BatteryResult:
    started = time.monotonic()
    try:
        with battery_lock(store.folder):
            adopted, _ = store.requeue_running()
            if reset:
                store.reset_failed(reset)
            _clear(store.folder / TMP_DIR)
            spec = store.spec()
            extend_all(store, spec)  # rounds a killed battery finished but did not schedule
            pending = store.ids("pending")
            finished = 0
            if pending:
                store.set_meta("session_started", str(time.time()))
                counts = store.counts()
                failed = sum(counts.get(s, 0) for s in FAILED_STATES)
                done = store.total() - len(pending)
                executor = executor or _executor(store, workers, dask, len(pending))
                try:
                    with _terminate_as_interrupt(), BatteryProgress(
                            store.total(), done, failed, enabled=progress) as bar:
                        finished = _loop(store, spec, executor, deque(pending), bar)
                except BaseException:
                    executor.close()  # kill the runs first, then requeue them
                    store.requeue_running()
                    raise
            return BatteryResult(store.folder, store.counts(), finished, adopted,
                                 time.monotonic() - started)
    finally:
        if executor is not None:
            executor.close()


def _loop(store: BatteryStore, spec: BatterySpec, executor: Executor, queue: deque[int],
          bar: BatteryProgress) -> int:
    token = uuid.uuid4().hex[:8]
    tmp = store.folder / TMP_DIR
    tmp.mkdir(exist_ok=True)
    (store.folder / WORKERS_DIR).mkdir(exist_ok=True)
    (store.folder / RUNS_DIR).mkdir(exist_ok=True)
    active: dict[int, Task] = {}
    rounds = Rounds(store, spec)  # under a stopping rule: each cell's next round
    finished = 0
    arrived: list[tuple[Task, Outcome]] = []
    while queue or active or arrived:
        # idle workers get their next run first; the runs that came back are put in
        # place after, while the workers are busy again
        while queue and executor.free() > 0:
            run_id = queue.popleft()
            attempt = store.start(run_id)
            task = store.task(run_id, attempt, spec, tmp / f"{run_id:05d}-a{attempt}-{token}")
            store.set_worker(run_id, executor.submit(task))
            active[run_id] = task
        for task, outcome in arrived:
            finish(store, task, outcome)
            finished += 1
            bar.advance(outcome.state)
            added = rounds.after(task.run_id)
            if added:
                queue.extend(added)
                bar.grow(len(added))
        arrived = []
        if not (queue or active):
            break
        for outcome in executor.poll(0.5):
            task = active.get(outcome.run_id)
            if task is None or task.attempt != outcome.attempt:
                continue
            del active[outcome.run_id]
            arrived.append((task, outcome))
    return finished


def finish(store: BatteryStore, task: Task, outcome: Outcome) -> None:
    """Put a run's folder in place with its outcome, then commit the outcome.

    The worker wrote the folder under a temporary name; the outcome goes into
    it as ``battery.json``, the folder is renamed to its final name (replacing
    an earlier attempt's), and only then is the database updated.
    """
    written = Path(task.folder)
    final = store.run_folder(task.run_id)
    written.mkdir(parents=True, exist_ok=True)
    (written / OUTCOME_FILE).write_text(outcome.to_json())
    if final.exists():
        shutil.rmtree(final)
    final.parent.mkdir(parents=True, exist_ok=True)
    os.replace(written, final)
    store.record(outcome)


def _executor(store: BatteryStore, workers: int | None, dask: str | None, pending: int
              ) -> Executor:
    if dask:
        from mimics.batteries.dask_backend import DaskExecutor

        refuse_dask(store.spec())
        return DaskExecutor(dask)
    from mimics.batteries.local import LocalExecutor

    count = min(workers or os.cpu_count() or 1, pending)
    return LocalExecutor(count, store.folder / WORKERS_DIR,
                         containment=containment_of(store.spec(), store.folder))


def _clear(folder: Path) -> None:
    if folder.is_dir():
        for item in folder.iterdir():
            if item.is_dir():
                shutil.rmtree(item, ignore_errors=True)
            else:
                item.unlink(missing_ok=True)


@contextlib.contextmanager
def _terminate_as_interrupt() -> Iterator[None]:
    """SIGTERM (a shutdown, ``kill``) stops the battery as Ctrl-C does: cleanly."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def interrupt(signum: int, frame: Any) -> None:
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


# -- the lock ------------------------------------------------------------------------

@contextlib.contextmanager
def battery_lock(folder: Path) -> Iterator[None]:
    """Hold the battery folder's lock, or fail naming the process that holds it.

    Raises:
        MimicsError: when another battery process works on the folder.
    """
    path = folder / LOCK_NAME
    fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        if not _try_lock(fd):
            pid = os.read(fd, 32).decode(errors="replace").strip() or "?"
            raise MimicsError(f"{folder}: a battery is already running on this folder (pid {pid})")
        os.ftruncate(fd, 0)
        os.write(fd, str(os.getpid()).encode())
        try:
            yield
        finally:
            _unlock(fd)
    finally:
        os.close(fd)


def lock_holder(folder: str | Path) -> int | None:
    """The pid of the battery process working on ``folder``, or None when none is."""
    path = Path(folder) / LOCK_NAME
    if not path.exists():
        return None
    fd = os.open(path, os.O_RDWR)
    try:
        if _try_lock(fd):
            _unlock(fd)
            return None
        text = os.read(fd, 32).decode(errors="replace").strip()
        return int(text) if text.isdigit() else -1
    finally:
        os.close(fd)


def _try_lock(fd: int) -> bool:
    try:
        if fcntl is not None:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        else:
            import msvcrt

            msvcrt.locking(fd, msvcrt.LK_NBLCK, 1)  # type: ignore[attr-defined]
    except OSError:
        return False
    return True


def _unlock(fd: int) -> None:
    with contextlib.suppress(OSError):
        if fcntl is not None:
            fcntl.flock(fd, fcntl.LOCK_UN)
        else:
            import msvcrt

            os.lseek(fd, 0, os.SEEK_SET)
            msvcrt.locking(fd, msvcrt.LK_UNLCK, 1)  # type: ignore[attr-defined]
