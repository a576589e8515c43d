"""Background jobs of the workbench (a run, a video export, a battery), with progress.

A job runs in a thread of the server; the page polls ``/api/jobs/{id}``. Jobs
are kept in memory only: a battery's progress comes from its SQLite state
instead, so that it survives a restart of the server.
"""

from __future__ import annotations

import itertools
import threading
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from mimics.world.errors import MimicsError


@dataclass
class Job:
    """One background task and what it reports.

    Attributes:
        id: its number.
        kind: ``"run"``, ``"export"`` or ``"battery"``.
        state: ``"running"``, ``"done"`` or ``"failed"``.
        done: units of work finished (frames, steps...).
        total: units of work in all (0: unknown).
        result: what it returned (JSON-able), when done.
        error: one line, when failed.
        label: what it works on (a battery folder...).
    """

    id: int
    kind: str
    state: str = "running"
    done: int = 0
    total: int = 0
    result: Any = None
    error: str = ""
    label: str = ""
    started: float = field(default_factory=time.time)

    def progress(self, done: int, total: int) -> None:
        """Report ``done`` of ``total`` units."""
        self.done, self.total = done, total

    def as_dict(self) -> dict[str, Any]:
        """The JSON form the API returns."""
        return {"id": self.id, "kind": self.kind, "state": self.state, "done": self.done,
                "total": self.total, "result": self.result, "error": self.error,
                "label": self.label, "elapsed": time.time() - self.started}


class Jobs:
    """The server's jobs, by id."""

    def __init__(self) -> None:
        self._jobs: dict[int, Job] = {}
        self._ids = itertools.count(1)
        self._lock = threading.Lock()

    def start(self, kind: str, work: Callable[[Job], Any], label: str = "") -> Job:
        """Run ``work(job)`` in a daemon thread; its return value becomes ``job.result``."""
        with self._lock:
            job = Job(next(self._ids), kind, label=label)
            self._jobs[job.id] = job

        def target() -> None:
            try:
                job.result = work(job)
                job.state = "done"
            except MimicsError as exc:
                job.error, job.state = str(exc), "failed"
            except Exception as exc:  # a bug must show in the page, not kill the server
                job.error = f"{type(exc).__name__}: {exc}"
                job.state = "failed"
                traceback.print_exc()

        threading.Thread(target=target, name=f"mimics-{kind}-{job.id}", daemon=True).start()
        return job

    def get(self, job_id: int) -> Job | None:
        """The job with this id, or None."""
        return self._jobs.get(job_id)

    def all(self, kind: str) -> list[Job]:
        """Jobs of ``kind``, oldest first."""
        return [j for j in self._jobs.values() if j.kind == kind]

    def running(self, kind: str) -> list[Job]:
        """Jobs of ``kind`` still running."""
        return [j for j in self._jobs.values() if j.kind == kind and j.state == "running"]
