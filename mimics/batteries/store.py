"""The state of a battery in SQLite: one ``battery.db`` per battery folder.

One row per run with its parameters, state (``pending``, ``running``,
``done``, ``error``, ``timeout``, ``crashed``), attempts, worker, start and end
times, outcome counts, error message and traceback. The database is in WAL
mode; every change is one transaction, so a battery killed at any instant
leaves it consistent. Only the battery process writes (readers such as
``mimics battery status`` may read while it runs).

A run's life: ``pending`` -> ``running`` (attempts + 1, committed before the
task leaves) -> its final state (committed after its folder has been renamed
into place, with the outcome in ``battery.json``). On resume, a ``running``
row whose folder holds the outcome of that very attempt is adopted (the
battery died between the rename and the commit); other ``running`` rows go
back to ``pending``.

>>> import tempfile
>>> from mimics.batteries.spec import spec_from_dict
>>> spec = spec_from_dict({"battery": {"algorithms": ["go_to_goal"], "seeds": 3},
...                        "scenarios": [{"name": "line", "robots": 2}]})
>>> store = BatteryStore.create(tempfile.mkdtemp(), spec)
>>> store.counts()
{'pending': 3}
"""

from __future__ import annotations

import contextlib
import json
import sqlite3
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from mimics.batteries.spec import BatterySpec, RunSpec
from mimics.batteries.tasks import COUNTS, FAILED_STATES, OUTCOME_FILE, STATES, Outcome, Task
from mimics.world.errors import MimicsError

DB_NAME = "battery.db"
RUNS_DIR = "runs"  # finished runs' folders
TMP_DIR = "tmp"  # runs being written
WORKERS_DIR = "workers"  # the workers' logs
SCHEMA_VERSION = "1"

_SCHEMA = f"""
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE runs (
    id INTEGER PRIMARY KEY,
    algorithm TEXT NOT NULL,
    algorithm_ref TEXT NOT NULL,
    scenario TEXT NOT NULL,
    scenario_ref TEXT NOT NULL,
    params TEXT NOT NULL,
    label TEXT NOT NULL,
    seed INTEGER NOT NULL,
    folder TEXT NOT NULL,
    state TEXT NOT NULL DEFAULT 'pending' CHECK (state IN ({", ".join(map(repr, STATES))})),
    attempts INTEGER NOT NULL DEFAULT 0,
    worker TEXT,
    started REAL,
    ended REAL,
    status TEXT,
    {", ".join(f"{c} INTEGER" for c in COUNTS)},
    sim_time REAL,
    wall_time REAL,
    error TEXT,
    traceback TEXT,
    metrics TEXT,
    digest TEXT,
    UNIQUE (algorithm_ref, scenario_ref, params, seed)
);
CREATE INDEX runs_by_state ON runs (state);
"""
#: Columns added since the first schema (a battery made before them gains them, empty).
_ADDED_COLUMNS = (("metrics", "TEXT"), ("digest", "TEXT"))


class BatteryStore:
    """A battery folder's database (use :meth:`create` or :meth:`open`)."""

    def __init__(self, folder: Path, connection: sqlite3.Connection) -> None:
        self.folder = folder
        self.db = connection

    # -- opening -----------------------------------------------------------------

    @classmethod
    def create(cls, folder: str | Path, spec: BatterySpec) -> BatteryStore:
        """Create ``folder/battery.db`` listing every run of ``spec``, all ``pending``.

        Raises:
            MimicsError: when the folder already holds a battery or is not empty.
        """
        root = Path(folder)
        cls.check_free(root)
        runs = spec.runs()
        try:
            root.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise MimicsError(f"{root}: cannot create the battery folder: {exc}") from None
        temporary = root / f".{DB_NAME}.new"
        temporary.unlink(missing_ok=True)
        db = _connect(temporary)
        with db:
            db.executescript(_SCHEMA)
        with _transaction(db):
            db.executemany("INSERT INTO meta VALUES (?, ?)", [
                ("schema", SCHEMA_VERSION), ("spec", spec.to_json()),
                ("created", str(time.time()))])
            db.executemany(
                "INSERT INTO runs (id, algorithm, algorithm_ref, scenario, scenario_ref, params, "
                "label, seed, folder) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                [(k, r.algorithm, r.algorithm_ref, r.scenario, r.scenario_ref,
                  json.dumps(r.params, sort_keys=True), r.label, r.seed, r.folder_name(k))
                 for k, r in enumerate(runs, start=1)])
        db.execute("PRAGMA wal_checkpoint(TRUNCATE)")
        db.close()
        for suffix in ("-wal", "-shm"):
            Path(f"{temporary}{suffix}").unlink(missing_ok=True)
        temporary.rename(root / DB_NAME)  # the battery exists only once every run is listed
        return cls.open(root)

    @staticmethod
    def check_free(folder: str | Path) -> None:
        """Check that a new battery can be created in ``folder`` (new or empty).

        Raises:
            MimicsError: when the folder already holds a battery or is not empty.
        """
        root = Path(folder)
        if (root / DB_NAME).exists():
            raise MimicsError(f"{root} already holds a battery: resume it with `mimics battery "
                              f"resume {root}`, or choose another --out")
        if root.exists() and (not root.is_dir() or any(root.iterdir())):
            raise MimicsError(f"{root} is not empty: choose a new or empty folder for --out")

    @classmethod
    def open(cls, folder: str | Path) -> BatteryStore:
        """Open an existing battery folder.

        Raises:
            MimicsError: when it is not a battery folder.
        """
        root = Path(folder)
        path = root / DB_NAME
        if not path.is_file():
            raise MimicsError(f"{root}: not a battery folder (no {DB_NAME})")
        try:
            db = _connect(path)
            version = db.execute("SELECT value FROM meta WHERE key = 'schema'").fetchone()
        except sqlite3.DatabaseError as exc:
            raise MimicsError(f"{path}: not a battery database ({exc})") from None
        if version is None or version[0] != SCHEMA_VERSION:
            raise MimicsError(f"{path}: unsupported battery database version {version}")
        _add_columns(db)
        return cls(root, db)

    def close(self) -> None:
        """Close the database connection."""
        self.db.close()

    # -- reading -----------------------------------------------------------------

    def spec(self) -> BatterySpec:
        """The battery's spec, as it was validated at creation."""
        return BatterySpec.from_json(self.meta("spec") or "{}")

    def meta(self, key: str) -> str | None:
        """A value of the meta table."""
        row = self.db.execute("SELECT value FROM meta WHERE key = ?", (key,)).fetchone()
        return None if row is None else row[0]

    def counts(self) -> dict[str, int]:
        """Runs by state (states with no run left out), in the order of ``STATES``."""
        found = dict(self.db.execute("SELECT state, count(*) FROM runs GROUP BY state"))
        return {s: found[s] for s in STATES if s in found}

    def total(self) -> int:
        """The number of runs."""
        return int(self.db.execute("SELECT count(*) FROM runs").fetchone()[0])

    def rows(self) -> list[dict[str, Any]]:
        """Every run as a dict of its columns, by id."""
        cursor = self.db.execute("SELECT * FROM runs ORDER BY id")
        names = [d[0] for d in cursor.description]
        return [dict(zip(names, row, strict=True)) for row in cursor]

    def ids(self, state: str) -> list[int]:
        """The ids of the runs in ``state``, in order."""
        return [r[0] for r in self.db.execute("SELECT id FROM runs WHERE state = ? ORDER BY id",
                                              (state,))]

    def finished_since(self, since: float) -> int:
        """Runs that ended at or after ``since`` (a Unix time)."""
        return int(self.db.execute("SELECT count(*) FROM runs WHERE ended >= ? AND state NOT IN "
                                   "('pending', 'running')", (since,)).fetchone()[0])

    def task(self, run_id: int, attempt: int, spec: BatterySpec, folder: Path) -> Task:
        """The task for one attempt at a run, writing into ``folder``."""
        row = self.db.execute("SELECT algorithm_ref, scenario_ref, params, seed FROM runs WHERE "
                              "id = ?", (run_id,)).fetchone()
        return Task(run_id=run_id, attempt=attempt, algorithm=row[0], scenario=row[1],
                    params=json.loads(row[2]), seed=int(row[3]), time=spec.time,
                    timeout=spec.timeout, policy=spec.policy, robot_logs=spec.robot_logs,
                    record_every=spec.record_every, record_scans=spec.record_scans,
                    ros_timeout=spec.ros_timeout, folder=str(Path(folder).resolve()),
                    log_dir=str((self.folder / WORKERS_DIR).resolve()))

    def run_folder(self, run_id: int) -> Path:
        """The final folder of a run."""
        row = self.db.execute("SELECT folder FROM runs WHERE id = ?", (run_id,)).fetchone()
        return self.folder / RUNS_DIR / row[0]

    # -- writing (the battery process only) --------------------------------------------

    def set_meta(self, key: str, value: str) -> None:
        """Set a value of the meta table."""
        with _transaction(self.db):
            self.db.execute("INSERT OR REPLACE INTO meta VALUES (?, ?)", (key, value))

    def start(self, run_id: int) -> int:
        """Mark a pending run ``running``; returns its attempt number."""
        with _transaction(self.db):
            self.db.execute("UPDATE runs SET state = 'running', attempts = attempts + 1, "
                            "started = ?, ended = NULL, worker = NULL WHERE id = ?",
                            (time.time(), run_id))
            return int(self.db.execute("SELECT attempts FROM runs WHERE id = ?",
                                       (run_id,)).fetchone()[0])

    def set_worker(self, run_id: int, worker: str) -> None:
        """Record which worker has a running run."""
        with _transaction(self.db):
            self.db.execute("UPDATE runs SET worker = ? WHERE id = ?", (worker, run_id))

    def record(self, outcome: Outcome) -> bool:
        """Store an attempt's outcome; False (and nothing stored) for a stale attempt."""
        counts = [outcome.counts.get(c) for c in COUNTS]
        with _transaction(self.db):
            cursor = self.db.execute(
                f"UPDATE runs SET state = ?, status = ?, worker = ?, started = ?, ended = ?, "
                f"{', '.join(f'{c} = ?' for c in COUNTS)}, sim_time = ?, wall_time = ?, "
                f"error = ?, traceback = ?, metrics = ?, digest = ? "
                f"WHERE id = ? AND attempts = ? AND state = 'running'",
                (outcome.state, outcome.status or None, outcome.worker, outcome.started,
                 outcome.ended, *counts, outcome.sim_time, outcome.wall_time, outcome.error,
                 outcome.traceback, json.dumps(outcome.metrics) if outcome.metrics else None,
                 outcome.digest or None, outcome.run_id, outcome.attempt))
            return cursor.rowcount == 1

    def add_runs(self, runs: list[RunSpec]) -> list[int]:
        """List more runs, ``pending`` (a stopping rule's next round); runs already
        listed (same algorithm, scenario, parameters and seed) are left as they are.

        Returns:
            The ids of the runs added, in order.
        """
        added = []
        with _transaction(self.db):
            next_id = int(self.db.execute("SELECT coalesce(max(id), 0) FROM runs").fetchone()[0])
            for run in runs:
                params = json.dumps(run.params, sort_keys=True)
                if self.db.execute(
                        "SELECT 1 FROM runs WHERE algorithm_ref = ? AND scenario_ref = ? AND "
                        "params = ? AND seed = ?",
                        (run.algorithm_ref, run.scenario_ref, params, run.seed)).fetchone():
                    continue
                next_id += 1
                found = self.db.execute(  # the cell's label as first listed (its key order)
                    "SELECT label FROM runs WHERE algorithm_ref = ? AND scenario_ref = ? AND "
                    "params = ? LIMIT 1", (run.algorithm_ref, run.scenario_ref, params)).fetchone()
                self.db.execute(
                    "INSERT INTO runs (id, algorithm, algorithm_ref, scenario, scenario_ref, "
                    "params, label, seed, folder) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?)",
                    (next_id, run.algorithm, run.algorithm_ref, run.scenario, run.scenario_ref,
                     params, found[0] if found else run.label, run.seed,
                     run.folder_name(next_id)))
                added.append(next_id)
        return added

    def requeue_running(self) -> tuple[int, int]:
        """After a battery died: adopt finished folders, set other running runs pending.

        Returns:
            (adopted, requeued) counts.
        """
        adopted = requeued = 0
        for run_id, attempts in list(self.db.execute(
                "SELECT id, attempts FROM runs WHERE state = 'running'")):
            outcome = _read_outcome(self.run_folder(run_id) / OUTCOME_FILE)
            if outcome is not None and (outcome.run_id, outcome.attempt) == (run_id, attempts):
                adopted += self.record(outcome)
            else:
                with _transaction(self.db):
                    self.db.execute("UPDATE runs SET state = 'pending' WHERE id = ?", (run_id,))
                requeued += 1
        return adopted, requeued

    def reset_failed(self, states: tuple[str, ...] = FAILED_STATES) -> int:
        """Set the runs in ``states`` back to ``pending``; returns how many."""
        bad = [s for s in states if s not in FAILED_STATES]
        if bad:
            raise MimicsError(f"--state: expected some of {', '.join(FAILED_STATES)}, got "
                              f"{', '.join(bad)}")
        with _transaction(self.db):
            marks = ", ".join("?" * len(states))
            cursor = self.db.execute(
                f"UPDATE runs SET state = 'pending' WHERE state IN ({marks})", states)
            return cursor.rowcount


def _add_columns(db: sqlite3.Connection) -> None:
    present = {row[1] for row in db.execute("PRAGMA table_info(runs)")}
    for name, kind in _ADDED_COLUMNS:
        if name not in present:
            with contextlib.suppress(sqlite3.OperationalError):  # a reader raced us to it
                db.execute(f"ALTER TABLE runs ADD COLUMN {name} {kind}")


def _connect(path: Path) -> sqlite3.Connection:
    db = sqlite3.connect(path, isolation_level=None, timeout=30.0)
    db.execute("PRAGMA journal_mode = WAL")
    db.execute("PRAGMA synchronous = NORMAL")
    db.execute("PRAGMA busy_timeout = 30000")
    return db


@contextlib.contextmanager
def _transaction(db: sqlite3.Connection) -> Iterator[None]:
    db.execute("BEGIN IMMEDIATE")
    try:
        yield
    except BaseException:
        db.execute("ROLLBACK")
        raise
    db.execute("COMMIT")


def _read_outcome(path: Path) -> Outcome | None:
    try:
        return Outcome.from_json(path.read_text())
    except (OSError, ValueError, TypeError):
        return None
