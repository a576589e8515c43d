"""Where a battery stands: runs by state, whether it is running, its rate and ETA."""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

from mimics.batteries.driver import lock_holder
from mimics.batteries.store import BatteryStore
from mimics.batteries.tasks import FAILED_STATES


@dataclass(frozen=True)
class BatteryStatus:
    """A snapshot of a battery folder.

    Attributes:
        folder: the battery folder.
        total: runs in the battery.
        counts: runs by state.
        pid: the battery process working on it (None when none is).
        rate: runs finished per second in the current (or last) session.
        eta: seconds until every run is finished at that rate (None: unknown).
        errors: the first failures as ``(run id, state, message)``.
    """

    folder: Path
    total: int
    counts: dict[str, int]
    pid: int | None
    rate: float | None
    eta: float | None
    errors: list[tuple[int, str, str]]

    @property
    def left(self) -> int:
        """Runs not finished yet (pending or running)."""
        return self.counts.get("pending", 0) + self.counts.get("running", 0)


def battery_status(folder: str | Path, max_errors: int = 10) -> BatteryStatus:
    """Read a battery's status (safe while it runs).

    Raises:
        MimicsError: when ``folder`` is not a battery folder.
    """
    store = BatteryStore.open(folder)
    try:
        counts = store.counts()
        total = store.total()
        since = float(store.meta("session_started") or 0.0)
        finished = store.finished_since(since) if since else 0
        errors = [(r[0], r[1], r[2] or "") for r in store.db.execute(
            f"SELECT id, state, error FROM runs WHERE state IN "
            f"({', '.join('?' * len(FAILED_STATES))}) ORDER BY id LIMIT ?",
            (*FAILED_STATES, max_errors))]
        last_end = store.db.execute("SELECT max(ended) FROM runs").fetchone()[0]
    finally:
        store.close()
    pid = lock_holder(folder)
    rate = eta = None
    end = time.time() if pid is not None else (last_end or time.time())
    if since and finished and end > since:
        rate = finished / (end - since)
    left = counts.get("pending", 0) + counts.get("running", 0)
    if rate and pid is not None:
        eta = left / rate
    elif left == 0:
        eta = 0.0
    return BatteryStatus(Path(folder), total, counts, pid, rate, eta, errors)
