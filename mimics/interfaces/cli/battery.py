"""`mimics battery ...`: set up, run, resume, re-run and report batteries.

A Typer sub-app; the main CLI mounts it with ``app.add_typer(battery_app,
name="battery")``. Every error a user can cause (a malformed battery file, an
unknown algorithm or scenario parameter, a folder that is not a battery) is
printed as one line ``mimics: error: ...`` on stderr with exit status 2, and
nothing is started.

    mimics battery new                       # pick algorithms, scenarios, seeds; saves battery.toml
    mimics battery run battery.toml --out batteries/night1 [--workers 2 | --dask tcp://host:8786]
    mimics battery run --last                # the last saved battery file
    mimics battery status batteries/night1   # runs by state, rate, ETA
    mimics battery resume batteries/night1   # after a kill, a reboot, a crash
    mimics battery add batteries/night1 late.py   # new algorithms: only their runs run
    mimics battery rerun-failed batteries/night1
    mimics battery report batteries/night1 [--csv out.csv] [--parquet out.parquet]
    mimics battery compare batteries/night1 [--baseline ALGO] [--metric M ...] [--csv out.csv]
    mimics battery run battery.toml --until time_to_goal:0.2   # seeds until the answer is known
    mimics battery run grading.toml --isolation run --sandbox bwrap   # a process per run, sandboxed
"""

from __future__ import annotations

import os
import time
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from mimics.interfaces.cli.battery_add import add_command
from mimics.interfaces.cli.battery_args import Folder, table_console
from mimics.interfaces.cli.battery_ends import finished, interrupted
from mimics.interfaces.cli.battery_new import new
from mimics.interfaces.cli.output import fail as _fail
from mimics.world.errors import MimicsError

app = typer.Typer(help="Batteries: algorithms x scenarios x seeds, unattended and resumable.",
                  no_args_is_help=True, rich_markup_mode=None)

Workers = Annotated[int | None, typer.Option(
    "--workers", "-w", help="Local worker processes [default: the number of CPU cores].")]
Dask = Annotated[str | None, typer.Option(
    help="Run on a Dask cluster: the scheduler's address (tcp://host:8786).")]
ShowProgress = Annotated[bool | None, typer.Option(
    "--progress/--no-progress", help="Progress bar [default: when on a terminal].")]
# -- new (battery_new.py), add (battery_add.py) ---------------------------------------

app.command("new")(new)
app.command("add")(add_command)


# -- run, resume, rerun-failed -------------------------------------------------------

@app.command()
def run(
    battery: Annotated[Path | None, typer.Argument(help="The battery file (TOML).")] = None,
    out: Annotated[Path | None, typer.Option(
        "--out", "-o", help="The battery folder [default: batteries/NAME-DATE-TIME].")] = None,
    last: Annotated[bool, typer.Option(
        "--last", help="Run the last saved battery file again.")] = False,
    workers: Workers = None,
    dask: Dask = None,
    progress: ShowProgress = None,
    until: Annotated[str | None, typer.Option(
        help="METRIC:HALF_WIDTH: run seeds 1, 2... in rounds per cell until the 95% interval "
             "of the metric's mean is at most HALF_WIDTH each side (as [battery.until]; "
             "min_seeds and max_seeds from the file's table, else 20 and 500).")] = None,
    isolation: Annotated[str | None, typer.Option(
        help="worker: a worker process runs many runs (fast); run: a fresh process per run, "
             "so no run sees what another left in a library [default: the file's "
             "[battery] isolation, else worker].")] = None,
    sandbox: Annotated[str | None, typer.Option(
        help="bwrap: each run under bubblewrap (read-only files, the submissions' and the "
             "battery's folders hidden, no network; implies --isolation run); none: no "
             "sandbox [default: the file's [battery] sandbox, else none].")] = None,
) -> None:
    """Run a battery: every run is listed in battery.db, then all run in parallel.

    Exceptions, hangs (past the timeout) and crashes of a run are recorded and
    the battery goes on. Stop it at any time; `mimics battery resume` goes on.
    Exit status 0 when every run finished (whatever its outcome), 1 when some
    could not (error, timeout, crashed: the count is printed), 2 for bad input.
    """
    from mimics.batteries.config import last_battery, remember_battery
    from mimics.batteries.driver import run_battery
    from mimics.batteries.spec import load_battery

    folder = out or Path("batteries")
    try:
        if battery is not None and last:
            raise MimicsError("give a battery file or --last, not both")
        if battery is None and not last:
            raise MimicsError("give a battery file (or --last for the last one saved)")
        path = last_battery() if last else battery
        assert path is not None
        spec = load_battery(path)
        if until is not None:
            from mimics.interfaces.cli.battery_report import with_until

            spec = with_until(spec, until)
        spec = _contained(spec, isolation, sandbox, dask)
        folder = out or Path("batteries") / f"{path.stem}-{time.strftime('%Y%m%d-%H%M%S')}"
        remember_battery(path)
        _announce(folder, len(spec.runs()), workers, dask, spec.until is not None)
        result = run_battery(spec, folder, workers=workers, dask=dask, progress=progress)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    except KeyboardInterrupt:
        raise interrupted(folder) from None
    finished(result)


@app.command()
def resume(folder: Folder, workers: Workers = None, dask: Dask = None,
           progress: ShowProgress = None) -> None:
    """Go on with a battery where it stopped (after a kill, a reboot, a crash).

    Finished runs are kept; runs left running by the dead battery run again.
    """
    from mimics.batteries.driver import resume_battery

    try:
        result = resume_battery(folder, workers=workers, dask=dask, progress=progress)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    except KeyboardInterrupt:
        raise interrupted(folder) from None
    finished(result)


@app.command("rerun-failed")
def rerun_failed_command(
    folder: Folder,
    state: Annotated[list[str] | None, typer.Option(
        help="Only runs in this state: error, timeout or crashed (repeatable) [default: all "
             "three].")] = None,
    workers: Workers = None,
    dask: Dask = None,
    progress: ShowProgress = None,
) -> None:
    """Run again, with the same seeds, the runs that failed (error, timeout, crashed).

    It helps runs that a machine stopped (a crash, a time-out on a busy machine); a run
    whose algorithm raised (state error) fails again the same way until its code changes.
    """
    from mimics.batteries.driver import rerun_failed
    from mimics.batteries.tasks import FAILED_STATES

    try:
        result = rerun_failed(folder, states=tuple(state or FAILED_STATES), workers=workers,
                              dask=dask, progress=progress)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    except KeyboardInterrupt:
        raise interrupted(folder) from None
    finished(result)


def _contained(spec: Any, isolation: str | None, sandbox: str | None, dask: str | None
               ) -> Any:
    """``spec`` with ``--isolation``/``--sandbox``; a sandbox without ``bwrap`` is refused
    here, before the battery folder is made."""
    from mimics.batteries.isolation import refuse_dask, with_options

    spec = with_options(spec, isolation, sandbox)
    if dask:
        refuse_dask(spec)
    if spec.sandbox:
        from mimics.batteries.sandbox import require_bwrap

        require_bwrap("--sandbox bwrap" if sandbox else "sandbox = \"bwrap\" (the battery file)")
    return spec


def _announce(folder: Path, runs: int, workers: int | None, dask: str | None,
              rounds: bool = False) -> None:
    where = f"the Dask cluster at {dask}" if dask else \
        f"{min(workers or os.cpu_count() or 1, runs)} local worker(s)"
    Console(stderr=True, highlight=False).print(
        f"battery {folder}: {runs} runs{' in the first round' if rounds else ''} on {where}",
        markup=False)


# -- status and report ---------------------------------------------------------------

@app.command()
def status(folder: Folder) -> None:
    """Runs by state, whether the battery is running, its rate and ETA, the first failures."""
    from mimics.batteries.status import battery_status
    from mimics.interfaces.cli.battery_report import duration, print_until_progress

    try:
        snapshot = battery_status(folder)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    console = table_console()
    table = Table(title=f"battery {folder}", show_header=False)
    table.add_column(style="bold")
    table.add_column(justify="right")
    for state, count in snapshot.counts.items():
        table.add_row(state, str(count))
    table.add_row("total", str(snapshot.total))
    running = (f"yes (pid {snapshot.pid})" if snapshot.pid is not None else
               "no" + (" (resume it with `mimics battery resume`)" if snapshot.left else ""))
    table.add_row("battery process", running)
    if snapshot.rate:
        rate = snapshot.rate
        table.add_row("rate", f"{rate:.1f} runs/s" if rate >= 1 else f"{rate * 60:.1f} runs/min")
    if snapshot.eta is not None:
        table.add_row("ETA", duration(snapshot.eta))
    console.print(table)
    print_until_progress(folder, console)
    for run_id, state, error in snapshot.errors:
        console.print(f"#{run_id} {state}: {error}", markup=False)

