"""``mimics battery report``: a battery's top-tier table, its exports and marks."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer
from rich.table import Table

from mimics.interfaces.cli.battery import Folder, _out
from mimics.interfaces.cli.output import fail as _fail
from mimics.world.errors import MimicsError


def report_command(
    folder: Folder,
    csv: Annotated[Path | None, typer.Option(help="Write one row per run as CSV.")] = None,
    parquet: Annotated[Path | None, typer.Option(
        help="Write one row per run as Parquet (with tracebacks).")] = None,
    misbehaving: Annotated[bool, typer.Option(
        help="List only the runs that misbehaved (failed, collisions, deadlocks...).")] = False,
    runs: Annotated[bool, typer.Option(
        "--runs/--no-runs", help="Print the per-run table (or only the aggregate).")] = True,
    grade: Annotated[Path | None, typer.Option(
        help="A grading file: grade(runs) turns the table into marks (printed, and written "
             "as CSV).")] = None,
    marks_csv: Annotated[Path | None, typer.Option(
        "--marks", help="Where --grade writes the marks [default: FOLDER/marks.csv].")] = None,
) -> None:
    """The top-tier table: one row per run (misbehaving runs marked) and per-algorithm means."""
    from mimics.batteries.report import export_table, print_report, runs_table

    try:
        table = runs_table(folder)
        print_report(table, _out(), only_misbehaving=misbehaving, runs=runs)
        for path, fmt in ((csv, "csv"), (parquet, "parquet")):
            if path is not None:
                export_table(table, path, fmt)
                _out().print(f"wrote {path}", markup=False)
        if grade is not None:
            _print_marks(table, grade, marks_csv or Path(folder) / "marks.csv")
    except MimicsError as exc:
        raise _fail(str(exc)) from None


def _print_marks(table: Any, grading_file: Path, out: Path) -> None:
    from mimics.batteries.grading import load_grader, marks

    result = marks(table, load_grader(grading_file), where=str(grading_file))
    rich_table = Table(title=f"marks ({grading_file.name})")
    frame = result.reset_index() if result.index.name else result
    for column in frame.columns:
        rich_table.add_column(str(column), justify="right" if column == "mark" else "left")
    for row in frame.itertuples(index=False):
        rich_table.add_row(*(str(value) for value in row))
    _out().print(rich_table)
    try:
        frame.to_csv(out, index=False)
    except OSError as exc:
        raise MimicsError(f"--marks {out}: cannot write it ({exc.strerror})") from None
    _out().print(f"wrote {out}", markup=False)
