"""One run of a battery as a task for a worker, and what comes back.

A :class:`Task` is everything a worker process needs (names, parameters,
seed, limits, the folder to write); :func:`execute` runs it inside the worker
and returns an :class:`Outcome`. Whatever the user's code does short of
killing the process (raising, returning NaN, calling ``sys.exit``) ends here
as an outcome; a hang or a dead process is turned into one by the parent
(:mod:`mimics.batteries.workers`).

Run states: ``done`` (the run ended normally, possibly with robots deactivated
for exceptions under the ``deactivate`` policy), ``error`` (status ``error``:
an exception under ``abort``, or the run could not start), ``timeout`` (past
the wall-clock limit) and ``crashed`` (the worker process died).
"""

from __future__ import annotations

import contextlib
import json
import os
import random
import re
import shutil
import sys
import tempfile
import time
import traceback
from collections.abc import Iterator
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

from mimics.batteries.states import FAILED_STATES as FAILED_STATES
from mimics.batteries.states import STATES as STATES

#: Engine status at the end of a run -> battery state.
STATE_OF_STATUS = {"completed": "done", "time_limit": "done", "stopped": "done",
                   "error": "error", "wall_limit": "timeout"}
#: Outcome counts copied from a run's summary.
COUNTS = ("robots", "reached_goal", "collisions", "escaped", "deadlocks", "livelocks",
          "exceptions")
#: The outcome file written into each run folder (what the database records for the run).
OUTCOME_FILE = "battery.json"


@dataclass(frozen=True)
class Task:
    """One attempt at one run, as sent to a worker."""

    run_id: int
    attempt: int
    algorithm: str
    scenario: str
    params: dict[str, Any]
    seed: int
    time: float | None
    timeout: float
    policy: str
    robot_logs: str
    record_every: int
    folder: str  # where the worker writes (a temporary name; the parent renames it)
    log_dir: str = ""  # where workers keep their stdout/stderr logs
    record_scans: bool = False  # also record the laser scans (scans.parquet)
    ros_timeout: float | None = None  # ros: algorithms' lockstep time-out (battery key)
    source: str = ""  # where the worker reads the algorithm file ("": the file itself; a
    # sandboxed run reads a copy, the submissions' folder being hidden from it)


@dataclass
class Outcome:
    """What became of one attempt at one run."""

    run_id: int
    attempt: int
    state: str
    status: str = ""
    error: str = ""
    traceback: str = ""
    worker: str = ""
    started: float = 0.0
    ended: float = 0.0
    wall_time: float | None = None
    sim_time: float | None = None
    counts: dict[str, int] = field(default_factory=dict)
    metrics: dict[str, Any] = field(default_factory=dict)  # metrics.summary_metrics
    digest: str = ""  # the run's fingerprint (metrics.run_digest)

    def to_json(self) -> str:
        """The outcome as JSON (the run folder's ``battery.json``)."""
        return json.dumps(asdict(self), indent=1)

    @classmethod
    def from_json(cls, text: str) -> Outcome:
        """An outcome written by :meth:`to_json`."""
        return cls(**json.loads(text))


def hard_timeout(timeout: float) -> float:
    """Seconds after dispatch at which a run's worker is killed.

    The engine stops a run by itself at ``timeout`` (its wall-clock limit) and
    writes its records; a run whose user code hangs never gets there, so its
    worker is killed a grace period later.
    """
    return timeout + min(30.0, max(2.0, 0.1 * timeout))


def _configure_scheme(task: Task) -> None:
    """Hand the battery's ``ros_timeout`` to a ``ros:`` algorithm's scheme (every task: a
    worker may have run another battery's before)."""
    from mimics.catalog import algorithm_scheme

    scheme = algorithm_scheme(task.algorithm)
    if scheme is not None and hasattr(scheme[0], "configure"):
        scheme[0].configure(timeout=task.ros_timeout,
                            option="ros_timeout in the battery file")


def execute(task: Task, worker: str) -> Outcome:
    """Run one task inside a worker process; never raises.

    User modules loaded from files are imported afresh for every run, and the
    global ``random`` and ``numpy.random`` generators are seeded with the run's
    seed, so a run's result does not depend on what the worker ran before.
    """
    import numpy as np

    started = time.time()
    outcome = Outcome(task.run_id, task.attempt, "error", worker=worker, started=started)
    for name in [n for n in sys.modules if n.startswith("mimics_user_")]:
        del sys.modules[name]  # user files (catalog._load_file): fresh module state per run
    random.seed(task.seed)
    np.random.seed(task.seed % 2**32)
    from mimics.engine.user_code import shown_path

    shown = shown_path(task.algorithm)  # as the teacher's working folder shows it
    with private_folder():  # the submission runs where it sees no other file
        original = task.algorithm
        source = task.source or original
        if original.endswith(".py") and Path(source).is_file():
            # a copy, alone in the folder: its __file__ leads to no classmate's file
            copy = Path.cwd() / Path(original).name
            shutil.copyfile(source, copy)
            task = replace(task, algorithm=str(copy))
        outcome = _execute(task, outcome)
        if task.algorithm != original:  # reasons name the submitted file, not the copy
            outcome.error = _named_as(outcome.error, task.algorithm, original, shown)
            outcome.traceback = _named_as(outcome.traceback, task.algorithm, original, shown)
        return outcome


def _named_as(text: str, copy: str, original: str, shown: str) -> str:
    """``text`` with the private copy's path (absolute, or relative to its folder: a
    failure's place) replaced by the submitted file's."""
    text = text.replace(copy, original)
    return re.sub(rf"(?<![\w/\\.]){re.escape(Path(copy).name)}(?=[:\"])", shown, text)


def _execute(task: Task, outcome: Outcome) -> Outcome:
    from mimics.batteries.metrics import run_digest, summary_metrics
    from mimics.catalog import find_algorithm
    from mimics.engine.user_code import LoadTimeout
    from mimics.records.layout import SUMMARY_JSON
    from mimics.records.runner import prepare, run_to_folder
    from mimics.world.errors import MimicsError

    try:
        _configure_scheme(task)
        # the submission's import, under the run's time-out (an endless loop at file level)
        find_algorithm(task.algorithm, load_limit=task.timeout)
        sim = prepare(task.scenario, task.algorithm, time=task.time, seed=task.seed,
                      policy=task.policy,  # type: ignore[arg-type]
                      wall_limit=task.timeout, params=task.params)
    except LoadTimeout as exc:
        outcome.state = "timeout"
        outcome.error = f"wall-clock timeout: {exc}"
        return _ended(outcome)
    except MimicsError as exc:
        outcome.error = f"the run could not start: {exc}"
        return _ended(outcome)
    except BaseException as exc:  # user code at import/build time
        outcome.error = f"the run could not start: {type(exc).__name__}: {exc}"
        outcome.traceback = traceback.format_exc()
        return _ended(outcome)
    Path(task.folder).parent.mkdir(parents=True, exist_ok=True)
    try:
        result = run_to_folder(sim, task.folder, robot_logs=task.robot_logs,  # type: ignore[arg-type]
                               every=task.record_every, record_scans=task.record_scans,
                               extra={"battery_run": task.run_id,
                                      "battery_attempt": task.attempt})
    except BaseException as exc:  # e.g. sys.exit() in user code
        outcome.error = f"the run raised {type(exc).__name__}: {exc}"
        outcome.traceback = traceback.format_exc()
        return _ended(outcome)
    summary = _written_summary(Path(task.folder) / SUMMARY_JSON) or result.summary()
    outcome.status = str(summary["status"])
    outcome.state = STATE_OF_STATUS.get(outcome.status, "error")
    outcome.wall_time = float(summary["wall_time"])
    outcome.sim_time = float(summary["sim_time"])
    outcome.counts = {key: int(summary[key]) for key in COUNTS}
    outcome.metrics = summary_metrics(summary)
    outcome.digest = run_digest(summary)
    outcome.error = str(summary.get("error") or "")
    if outcome.state == "timeout":  # a step that did not return: its robot, step and line
        outcome.error = (f"wall-clock timeout: {outcome.error}" if outcome.error else
                         f"wall-clock timeout: stopped after {task.timeout:g} s at simulated "
                         f"t={outcome.sim_time:g} s")
    if outcome.state == "error" or outcome.error:
        first = next((e for e in result.events if e.kind == "exception"), None)
        outcome.traceback = first.traceback if first is not None else ""
    return _ended(outcome)


@contextlib.contextmanager
def private_folder() -> Iterator[None]:
    """Run the body in a new empty working folder (removed after): a submission's relative
    paths (``open("bob.py")``) reach no classmate's file."""
    before = os.getcwd()
    folder = tempfile.mkdtemp(prefix="mimics-run-")
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(before)
        shutil.rmtree(folder, ignore_errors=True)


def _written_summary(path: Path) -> dict[str, Any] | None:
    """The run folder's summary.json: the engine's summary with what the recorder adds
    (such as ``trajectory_digest``, which the run's digest reads when present)."""
    try:
        data = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return data if isinstance(data, dict) else None


def _ended(outcome: Outcome) -> Outcome:
    outcome.ended = time.time()
    if outcome.wall_time is None:
        outcome.wall_time = outcome.ended - outcome.started
    return outcome

