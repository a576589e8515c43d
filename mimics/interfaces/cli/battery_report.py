"""``mimics battery report`` and ``compare``: a battery's tables, intervals, paired
comparisons, exports and marks; the stopping rule's progress for ``status``."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from mimics.interfaces.cli.battery_args import Folder, battery_records, table_console
from mimics.interfaces.cli.output import fail as _fail
from mimics.world.errors import MimicsError

Baseline = Annotated[str | None, typer.Option(
    help="The algorithm the others are compared with [default: the battery's first].")]
Metrics = Annotated[list[str] | None, typer.Option(
    "--metric", "-m", help="A per-run metric (repeatable): success, reached_goal, collisions, "
    "deadlocks, livelocks, escaped, exceptions, time_to_goal (restricted mean: non-arrivals at "
    "the horizon), time_to_goal_arrived, path_length, path_efficiency, sim_time, wall_time, "
    "user_time [default: the battery's primary metric, success, time_to_goal, reached_goal, "
    "collisions].")]
ExcludeFailed = Annotated[bool, typer.Option(
    "--exclude-failed", help="Leave failed runs (error, time-out, crash) out of rates and "
    "comparisons, on purpose [default: they count, as success 0 and reached 0].")]
Adjust = Annotated[str, typer.Option(
    help="How p-values are adjusted for the number of tests shown: holm, bh or none.")]
Interval = Annotated[str, typer.Option(
    "--interval", help="Interval of a mean: t (Student t corrected for skewness, Hall 1992) "
    "or bootstrap (BCa; for paired differences, the bootstrap of their mean), for skewed "
    "metrics).")]


def _evidence(folder: Path, baseline: str | None, metric: list[str] | None,
              exclude_failed: bool, adjust: str, interval: str) -> Any:
    from mimics.batteries.evidence import battery_evidence

    return battery_evidence(folder, baseline=baseline, metrics=metric,
                            exclude_failed=exclude_failed, adjust=adjust, method=interval)


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
    students: Annotated[Path | None, typer.Option(
        help="With --grade: the class list, a CSV file,student_id[,name] whose ids key the "
             "marks, feedback and leaderboard [default: students.csv next to the battery "
             "file, if any].")] = None,
    baseline: Baseline = None,
    metric: Metrics = None,
    exclude_failed: ExcludeFailed = False,
    adjust: Adjust = "holm",
    interval: Interval = "t",
) -> None:
    """The top-tier table: one row per run (misbehaving runs marked), the failed runs,
    each cell's intervals, the paired comparison against a baseline, the costs and the
    identical-seed warnings.

    With --grade: the marks, each with its reason, written as marks.csv, with a feedback
    file per student (FOLDER/feedback/ID.md) and a leaderboard (FOLDER/leaderboard.csv
    and .html: mark, then mean time to goal)."""
    from mimics.batteries.printing import print_report
    from mimics.batteries.report import export_table
    from mimics.world.output_paths import check_outputs

    try:
        marks_out = marks_csv or (Path(folder) / "marks.csv" if grade is not None else None)
        # before reading: an export over battery.db or a run's file would lose the battery
        check_outputs({"--csv": csv, "--parquet": parquet, "--marks": marks_out},
                      {"the battery folder": battery_records(folder), "--grade": grade,
                       "--students": students})
        if students is not None and grade is None:
            raise MimicsError("--students: only with --grade (it keys the marks)")
        evidence = _evidence(folder, baseline, metric, exclude_failed, adjust, interval)
        print_report(evidence, table_console(), only_misbehaving=misbehaving, runs=runs)
        for path, fmt in ((csv, "csv"), (parquet, "parquet")):
            if path is not None:
                export_table(evidence.table, path, fmt)
                table_console().print(f"wrote {path}", markup=False)
        if grade is not None:
            _print_marks(folder, evidence.table, grade, marks_out or Path(folder) / "marks.csv",
                         students)
    except MimicsError as exc:
        raise _fail(str(exc)) from None


def _print_marks(folder: Path, table: Any, grading_file: Path, out: Path,
                 students_file: Path | None) -> None:
    from mimics.batteries.grading import load_grader
    from mimics.batteries.grading.course import grade_class, write_class
    from mimics.batteries.grading.students import default_students_file, read_students
    from mimics.batteries.store import BatteryStore

    store = BatteryStore.open(folder)
    try:
        spec = store.spec()
    finally:
        store.close()
    base = Path(spec.source).parent if spec.source else None
    roster_file = students_file or default_students_file(spec.source)
    roster = read_students(roster_file) if roster_file is not None else None
    grades = grade_class(table, load_grader(grading_file), where=str(grading_file),
                         students=roster, base=base)
    rich_table = Table(title=f"marks ({grading_file.name})")
    shown = grades.table.drop(columns=["time_to_goal"])
    for column in shown.columns:
        rich_table.add_column(str(column), justify="right" if column == "mark" else "left")
    for row in shown.itertuples(index=False):
        rich_table.add_row(*("" if _blank(value) else str(value) for value in row))
    console = table_console()
    console.print(rich_table)
    title = f"{spec.name or Path(folder).name}: leaderboard"
    for path in write_class(grades, Path(folder), out, title=title):
        console.print(f"wrote {path}", markup=False)
    if roster_file is not None:
        console.print(f"student ids from {roster_file}", markup=False)


def _blank(value: Any) -> bool:
    return value is None or (isinstance(value, float) and value != value)


def compare_command(
    folder: Folder,
    baseline: Baseline = None,
    metric: Metrics = None,
    csv: Annotated[Path | None, typer.Option(help="Also write the comparison as CSV.")] = None,
    exclude_failed: ExcludeFailed = False,
    adjust: Adjust = "holm",
    interval: Interval = "t",
) -> None:
    """Each algorithm against the baseline, paired by scenario, parameters and seed. Failed
    runs are named first and count (success 0); success rates by Newcombe's paired interval
    and McNemar's exact test, means by the t interval and the Wilcoxon signed-rank test;
    each p-value also Holm-adjusted for the tests shown; then each cell's intervals."""
    from mimics.batteries.printing import print_evidence, print_warnings
    from mimics.world.output_paths import check_outputs

    try:
        check_outputs({"--csv": csv}, {"the battery folder": battery_records(folder)})
        evidence = _evidence(folder, baseline, metric, exclude_failed, adjust, interval)
        if evidence.table.empty:
            raise MimicsError(f"{folder}: the battery has no runs")
        console = table_console()
        print_evidence(evidence, console)
        if evidence.comparison.empty:
            console.print("one algorithm only: nothing to compare", markup=False)
        else:
            console.print(f"{evidence.tests} tests; p adjusted by {adjust}"
                          + (f"; primary metric: {evidence.primary}" if evidence.primary
                             else ""), markup=False)
        if csv is not None:
            try:
                evidence.comparison.to_csv(csv, index=False)
            except OSError as exc:
                raise MimicsError(f"--csv {csv}: cannot write it ({exc.strerror})") from None
            console.print(f"wrote {csv}", markup=False)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    print_warnings(evidence, Console(stderr=True, highlight=False, soft_wrap=True))


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
    from mimics.batteries.report import runs_table
    from mimics.batteries.seed_warnings import identical_seed_warnings

    console = Console(stderr=True, highlight=False, soft_wrap=True)
    for line in identical_seed_warnings(runs_table(folder)):
        console.print(f"mimics: warning: {line}", markup=False)


def print_until_progress(folder: Path, console: Console) -> None:
    """The stopping rule's progress per cell (nothing for a battery without one)."""
    from mimics.batteries.rounds import folder_until_status

    spec, cells = folder_until_status(folder)
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
