"""``mimics battery add FOLDER FILE...``: late submissions, run without re-running the others.

The new ``.py`` files join the battery's algorithms (its stored spec and its
database learn them) and only their runs are run, on the battery's scenarios and
seeds; every run already in the battery is left as it is. A file whose name (its
stem: the algorithm's name in the marks) the battery already has is refused,
unless ``--replace``: the old file's runs (rows and folders) are then dropped and
the new file's run in their place. Reports afterwards include the new files.

    mimics battery add class-1 submissions/zoe.py submissions/yann.py
    mimics battery add class-1 submissions/alice.py --replace   # a corrected resubmission
"""

from __future__ import annotations

import json
import shutil
from dataclasses import replace
from pathlib import Path
from typing import Annotated, Any

import typer

from mimics.interfaces.cli.battery_args import Folder
from mimics.interfaces.cli.battery_ends import finished, interrupted
from mimics.interfaces.cli.output import fail as _fail
from mimics.world.errors import MimicsError


def add_command(
    folder: Folder,
    files: Annotated[list[Path], typer.Argument(
        help="The submissions to add (.py files), e.g. submissions/zoe.py.")],
    replace_old: Annotated[bool, typer.Option(
        "--replace", help="Run a file whose name the battery already has again, dropping "
             "the old file's runs [default: such a file is refused].")] = False,
    workers: Annotated[int | None, typer.Option(
        "--workers", "-w", help="Local worker processes [default: the number of CPU "
                                "cores].")] = None,
    progress: Annotated[bool | None, typer.Option(
        "--progress/--no-progress", help="Progress bar [default: when on a terminal].")] = None,
) -> None:
    """Add submissions to an existing battery and run only their runs.

    Exit status as `battery resume`: 0 when every run of the battery finished, 1 when
    some could not (theirs or earlier ones), 2 for bad input (nothing is changed then).
    """
    from mimics.batteries.driver import resume_battery

    try:
        added = add_algorithms(folder, files, replace_old=replace_old)
        _announce(folder, added)
        result = resume_battery(folder, workers=workers, progress=progress)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    except KeyboardInterrupt:
        raise interrupted(folder) from None
    finished(result)


def add_algorithms(folder: str | Path, files: list[Path], *, replace_old: bool = False
                   ) -> list[int]:
    """Add ``files`` to the battery in ``folder``: its spec and one pending run per
    scenario point and seed of each; with ``replace_old``, a file whose name the battery
    already has takes the old one's place (its runs and their folders removed first).

    Returns:
        The ids of the runs added.

    Raises:
        MimicsError: not a battery folder, a battery running on it, a file that is not
            an existing ``.py`` file, two files of one name, or a name already in the
            battery without ``replace_old``; nothing is changed then.
    """
    from mimics.batteries.driver import battery_lock
    from mimics.batteries.references import algorithm_label
    from mimics.batteries.store import BatteryStore

    if not files:
        raise MimicsError("battery add: expected one or more .py files after the folder")
    refs: list[str] = []
    for file in files:
        if file.suffix != ".py":
            raise MimicsError(f"{file}: expected a .py file (a submission)")
        if not file.is_file():
            raise MimicsError(f"{file}: no such file")
        refs.append(str(file.resolve()))
    names = [algorithm_label(ref) for ref in refs]
    twice = next((n for n in names if names.count(n) > 1), None)
    if twice is not None:
        raise MimicsError(f"two files named {twice}.py given: each name is one student's row "
                          "in the marks")
    store = BatteryStore.open(folder)
    try:
        with battery_lock(store.folder):
            spec = store.spec()
            if spec.until is not None:
                raise MimicsError(f"{folder}: a battery with a stopping rule ([battery.until]) "
                                  "cannot take new algorithms")
            known = {algorithm_label(ref): ref for ref in spec.algorithms}
            clash = [(name, file) for name, file in zip(names, files, strict=True)
                     if name in known]
            if clash and not replace_old:
                name, file = clash[0]
                raise MimicsError(f"{file}: the battery already has {name} ({known[name]}); "
                                  f"give --replace to run the new file in its place")
            algorithms = list(spec.algorithms)
            for name, _ in clash:
                _drop_runs(store, known[name])
                algorithms.remove(known[name])
            algorithms.extend(refs)
            store.set_meta("spec", replace(spec, algorithms=tuple(algorithms)).to_json())
            added = store.add_runs(replace(spec, algorithms=tuple(refs)).runs())
            _log_addition(store, refs, [name for name, _ in clash])
            return added
    finally:
        store.close()


def _drop_runs(store: Any, ref: str) -> None:
    """Remove an algorithm's runs: their folders, then their rows."""
    from mimics.batteries.store import RUNS_DIR

    rows = store.db.execute("SELECT folder FROM runs WHERE algorithm_ref = ?", (ref,)).fetchall()
    for (name,) in rows:
        shutil.rmtree(store.folder / RUNS_DIR / name, ignore_errors=True)
    store.db.execute("BEGIN IMMEDIATE")
    try:
        store.db.execute("DELETE FROM runs WHERE algorithm_ref = ?", (ref,))
    except BaseException:
        store.db.execute("ROLLBACK")
        raise
    store.db.execute("COMMIT")


def _log_addition(store: Any, refs: list[str], replaced: list[str]) -> None:
    """Keep a record of additions in the battery's meta table (``added``: a JSON list)."""
    import time

    history = json.loads(store.meta("added") or "[]")
    history.append({"time": time.time(), "files": refs, "replaced": replaced})
    store.set_meta("added", json.dumps(history))


def _announce(folder: Path, added: list[int]) -> None:
    from rich.console import Console

    Console(stderr=True, highlight=False).print(
        f"battery {folder}: {len(added)} new run(s) added; the runs already there are kept",
        markup=False)
