"""Command-line front ends of run records: `mimics report RUN`, `mimics logs export RUN`.

Plain Typer pieces; the main CLI registers them::

    app.command("report")(report_command)
    app.add_typer(logs_app, name="logs")

Every error a user can cause (not a run folder, a truncated Parquet file, a
robot that does not exist) is printed as one line ``mimics: error: ...`` on
stderr and exits with status 2.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from mimics.interfaces.cli.output import fail as _fail
from mimics.world.errors import MimicsError

logs_app = typer.Typer(help="Per-robot text logs of a run (the paper's form).",
                       no_args_is_help=True, rich_markup_mode=None)




def report_command(
    run: Annotated[Path, typer.Argument(help="A run folder (written by `mimics run`).")],
) -> None:
    """Print a run's summary: outcome, counts, times, user-code timing, path statistics.

    Reads only summary.json (and scenario.toml for a run that did not finish);
    a folder that is not a run, or a truncated file, is reported in one line.
    """
    from mimics.records.run_folder import load_run
    from mimics.records.summary import summary_rows

    try:
        loaded = load_run(run)
        summary = loaded.summary
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    title = (f"{summary.get('scenario', '?')} / {summary.get('algorithm', '?')} / seed "
             f"{summary.get('seed', '?')}")
    table = Table(title=title, show_header=False)
    table.add_column(style="bold")
    table.add_column()
    for label, value in summary_rows(summary):
        table.add_row(label, value)
    console = Console(highlight=False)
    console.print(table)
    if not loaded.complete:
        console.print(f"{run}: the run did not finish (no summary.json); its records hold "
                      "what was written before it stopped", markup=False)


@logs_app.command("export")
def export_command(
    run: Annotated[Path, typer.Argument(help="A run folder (written by `mimics run`).")],
    robot: Annotated[list[int] | None, typer.Option(
        help="Only this robot (0-based index, as in the file names); repeatable.")] = None,
    out: Annotated[Path | None, typer.Option(
        help="Folder for the logs [default: RUN/robots].")] = None,
) -> None:
    """Write the per-robot logs (robots/robot_0000.log ...) from trajectory.parquet.

    Robot numbers are the engine's 0-based indices: robot_0000.log is robot 0.
    Works on runs recorded without logs (large teams) and on runs that did not
    finish (from what was written).
    """
    from mimics.records.layout import ROBOTS_DIR, run_records
    from mimics.records.robot_logs import write_robot_logs
    from mimics.records.run_folder import load_run
    from mimics.world.output_paths import check_outputs

    try:  # the logs may go to RUN/robots (their default), never over another record
        check_outputs({"--out": out}, {"the run folder": run_records(run, but=(ROBOTS_DIR,))})
        loaded = load_run(run)
        written = write_robot_logs(loaded.path, loaded.scenario, loaded.info, robots=robot,
                                   out=out)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    where = written[0].parent if written else (out or run)
    Console(highlight=False, soft_wrap=True).print(f"wrote {len(written)} robot logs in {where}",
                                                   markup=False)
