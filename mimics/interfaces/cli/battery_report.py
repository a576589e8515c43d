"""``mimics battery report`` and ``compare``: a battery's tables, intervals, paired
comparisons, exports and marks; the stopping rule's progress for ``status``."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from mimics.interfaces.cli.battery_args import Folder, table_console
from mimics.interfaces.cli.output import fail as _fail
from mimics.world.errors import MimicsError

Baseline = Annotated[str | None, typer.Option(
    help="The algorithm the others are compared with [default: the battery's first].")]
Metrics = Annotated[list[str] | None, typer.Option(
    "--metric", "-m", help="A per-run metric (repeatable): success, reached_goal, collisions, "
    "deadlocks, livelocks, escaped, exceptions, time_to_goal, path_length, path_efficiency, "
    "sim_time, wall_time [default: success, reached_goal, collisions, time_to_goal, "
    "path_efficiency, wall_time].")]


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
    baseline: Baseline = None,
    metric: Metrics = None,
) -> None:
    """The top-tier table: one row per run (misbehaving runs marked), each cell's means
    with 95% intervals, the paired comparison against a baseline, identical-seed warnings."""
    from mimics.batteries.comparison import check_metrics
    from mimics.batteries.report import export_table, print_report, runs_table

    try:
        chosen = check_metrics(metric)
        table = runs_table(folder)
        print_report(table, table_console(), only_misbehaving=misbehaving, runs=runs,
                     baseline=baseline, metrics=chosen)
        for path, fmt in ((csv, "csv"), (parquet, "parquet")):
            if path is not None:
                export_table(table, path, fmt)
                table_console().print(f"wrote {path}", markup=False)
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
    table_console().print(rich_table)
    try:
        frame.to_csv(out, index=False)
    except OSError as exc:
        raise MimicsError(f"--marks {out}: cannot write it ({exc.strerror})") from None
    table_console().print(f"wrote {out}", markup=False)


def compare_command(
    folder: Folder,
    baseline: Baseline = None,
    metric: Metrics = None,
    csv: Annotated[Path | None, typer.Option(help="Also write the comparison as CSV.")] = None,
) -> None:
    """Each algorithm against the baseline, paired by scenario, parameters and seed: the mean
    difference of each metric with its 95% t interval, the Wilcoxon signed-rank p-value
    (SciPy) and the number of pairs; then each cell's intervals."""
    from mimics.batteries.comparison import cell_intervals, check_metrics, paired_comparison
    from mimics.batteries.report import runs_table
    from mimics.batteries.tables import comparison_rich, intervals_rich

    try:
        chosen = check_metrics(metric)
        table = runs_table(folder)
        if table.empty:
            raise MimicsError(f"{folder}: the battery has no runs")
        comparison = paired_comparison(table, baseline, chosen)
        console = table_console()
        console.print(intervals_rich(cell_intervals(table, chosen), chosen))
        if comparison.empty:
            console.print("one algorithm only: nothing to compare", markup=False)
        else:
            console.print(comparison_rich(comparison))
        if csv is not None:
            try:
                comparison.to_csv(csv, index=False)
            except OSError as exc:
                raise MimicsError(f"--csv {csv}: cannot write it ({exc.strerror})") from None
            console.print(f"wrote {csv}", markup=False)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    print_warnings(folder)


def with_until(spec: Any, text: str) -> Any:
    """The spec with the stopping rule of ``--until METRIC:HALF_WIDTH``.

    Raises:
        MimicsError: naming ``--until``.
    """
    from dataclasses import replace

    from mimics.batteries.until import parse_until_option

    rule = parse_until_option(text, MimicsError, spec.until)
    return replace(spec, until=rule, seeds=tuple(range(1, rule.min_seeds + 1)))


def print_warnings(folder: Path) -> None:
    """One line on stderr per cell whose seeds gave identical runs."""
    from mimics.batteries.comparison import identical_seed_warnings, randomize_hints
    from mimics.batteries.report import runs_table

    table = runs_table(folder)
    console = Console(stderr=True, highlight=False, soft_wrap=True)
    for line in identical_seed_warnings(table, randomize_hints(table) if len(table) else {}):
        console.print(f"mimics: warning: {line}", markup=False)


def print_until_progress(folder: Path, console: Console) -> None:
    """The stopping rule's progress per cell (nothing for a battery without one)."""
    from mimics.batteries.rounds import until_status
    from mimics.batteries.store import BatteryStore

    store = BatteryStore.open(folder)
    try:
        spec = store.spec()
        cells = until_status(store, spec)
    finally:
        store.close()
    if spec.until is None:
        return
    rule = spec.until
    table = Table(title=f"until the 95% interval of {rule.metric} is within ± "
                        f"{rule.half_width:g} (seeds {rule.min_seeds} to {rule.max_seeds})",
                  header_style="bold")
    for name in ("algorithm", "scenario", "parameters", "seeds run", "scheduled",
                 "half-width", "state"):
        table.add_column(name, justify="left" if name in ("algorithm", "scenario",
                                                         "parameters", "state") else "right")
    for cell in (c.as_dict() for c in cells):
        width = cell["half_width"]
        table.add_row(cell["algorithm"], cell["scenario"], cell["parameters"],
                      str(cell["seeds"]), str(cell["scheduled"]),
                      "-" if width is None else f"{width:.3g}",
                      cell["state"])
    console.print(table)


def duration(seconds: float) -> str:
    """``"1h02m03s"`` or ``"2m03s"``."""
    whole = round(seconds)
    hours, rest = divmod(whole, 3600)
    minutes, secs = divmod(rest, 60)
    return f"{hours}h{minutes:02d}m{secs:02d}s" if hours else f"{minutes}m{secs:02d}s"
