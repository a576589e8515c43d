"""The ``mimics`` command line.

Every error a user can cause (an unknown name, a bad number, a malformed file)
is printed as one line on stderr and exits with status 2.
"""

from __future__ import annotations

import functools
import sys
import tomllib
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from mimics.interfaces.cli.output import fail, note
from mimics.interfaces.cli.values import guard_values
from mimics.world.errors import MimicsError

HELP = """mimics: a fast multi-robot simulator for teaching, prototyping and batteries.

\b
Exit status (every command):
  0    done as asked: a run ended by its end criteria (all robots finished,
       time or wall-clock limit, stop predicate), whatever its collisions;
       a battery whose runs all finished, whatever their outcomes
  1    it ran, but failed: a run ended in error (user code raised under
       --policy abort); battery runs that could not finish (error, timeout,
       crashed), with their count
  2    bad input: an option, a file or a name is wrong, or the run would
       not fit in memory; one line `mimics: error: ...`, nothing started
  130  interrupted (Ctrl-C); a battery keeps its finished runs
"""

app = typer.Typer(
    name="mimics",
    help=HELP,
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)
list_app = typer.Typer(help="List built-in algorithms, scenarios or robot types.",
                       no_args_is_help=True)
app.add_typer(list_app, name="list")

console = Console()

#: Exit statuses (see HELP and docs/reference/exit-status.md).
EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_INTERRUPTED = 0, 1, 2, 130


@app.callback()
def root(ctx: typer.Context) -> None:
    """Check every number and text given to any command before it runs (cli/values.py)."""
    guard_values(ctx.find_root().command)


def parse_params(items: list[str]) -> dict[str, Any]:
    """``["robots=200", "x_offset=0.5"]`` to a dict, values read as TOML literals."""
    params: dict[str, Any] = {}
    for item in items:
        key, sep, text = item.partition("=")
        if not sep or not key.strip():
            raise MimicsError(f"--param {item!r}: expected NAME=VALUE")
        try:
            value = tomllib.loads(f"v = {text}")["v"]
        except tomllib.TOMLDecodeError:
            value = text
        params[key.strip()] = value
    return params


def print_summary(summary: dict[str, Any], out: Path | None) -> None:
    """A short table of a run's outcome."""
    table = Table(title=f"{summary['scenario']} / {summary['algorithm']} / seed "
                        f"{summary['seed']}: {summary['status']}", show_header=False)
    table.add_column(style="bold")
    table.add_column(justify="right")
    rows = [("robots", summary["robots"]), ("reached goal", summary["reached_goal"]),
            ("collisions", summary["collisions"]), ("escaped", summary["escaped"]),
            ("deadlocks", summary["deadlocks"]), ("livelocks", summary["livelocks"]),
            ("exceptions", summary["exceptions"]),
            ("simulated time", f"{summary['sim_time']:.2f} s"),
            ("wall time", f"{summary['wall_time']:.2f} s"),
            ("speed", f"{summary['sim_speed']:.2f} s_sim/s" if summary["sim_speed"] else "-")]
    from mimics.engine.compile_clock import compile_seconds

    if compile_seconds() >= 0.05:  # this process compiled kernels: not the run's own time
        rows.append(("compile", f"{compile_seconds():.1f} s (first run: kernels cached for "
                                "later runs)"))
    for name, value in rows:
        table.add_row(name, str(value))
    console.print(table)
    if summary.get("error"):
        console.print(f"error: {summary['error']}", markup=False)
    if out is not None:
        console.print(f"records in {out}", markup=False)


@app.command()
def run(
    scenario: Annotated[str, typer.Argument(help="Built-in scenario name or a .py/.toml file.")],
    algorithm: Annotated[str, typer.Argument(help="Built-in algorithm name or a .py, .c or "
                                                  ".cpp file.")],
    robots: Annotated[int | None, typer.Option(help="Number of robots (scenario parameter).")]
    = None,
    time: Annotated[float | None, typer.Option(help="Simulated seconds to run.")] = None,
    seed: Annotated[int, typer.Option(help="Seed of every random draw.")] = 0,
    out: Annotated[Path | None, typer.Option(help="Run folder [default: runs/SCENARIO-ALGO-sSEED]"
                                             )] = None,
    policy: Annotated[str, typer.Option(help="On user exceptions: abort or deactivate.")]
    = "abort",
    param: Annotated[list[str] | None, typer.Option(help="Scenario parameter NAME=VALUE "
                                                         "(repeatable).")] = None,
    wall_limit: Annotated[float | None, typer.Option(help="Stop after this many wall seconds."
                                                     )] = None,
    robot_logs: Annotated[str, typer.Option(help="Per-robot text logs: auto, on or off.")]
    = "auto",
    view: Annotated[str, typer.Option(help="Live view: step, 1s, 10s or off.")] = "off",
    video: Annotated[Path | None, typer.Option(help="Also export a video of the run.")] = None,
    record_scans: Annotated[bool, typer.Option("--record-scans", help="Also record the laser "
                                               "scans (scans.parquet, 1 mm steps).")] = False,
    allow_overlap: Annotated[bool, typer.Option(
        help="Keep robots that start touching a wall or each other, or outside the map "
             "(reported, then run).")] = False,
) -> None:
    """Run one simulation, print its summary and write its run folder.

    Exit status 0 when the run ended by its end criteria, 1 when it ended in
    error (user code raised under --policy abort), 2 for bad input.
    """
    from mimics.interfaces.cli.native import needs_child, run_in_child

    if needs_child(algorithm):  # compiled code may crash: run it in a child process
        raise typer.Exit(run_in_child(dict(
            scenario=scenario, algorithm=algorithm, robots=robots, time=time, seed=seed,
            out=out, policy=policy, param=param, wall_limit=wall_limit, robot_logs=robot_logs,
            view=view, video=video, record_scans=record_scans, allow_overlap=allow_overlap)))
    from mimics.records.runner import prepare, run_to_folder

    if policy not in ("abort", "deactivate"):
        raise fail(f"--policy: expected abort or deactivate, got {policy!r}")
    if robots is not None and robots < 1:
        raise fail(f"--robots: expected a whole number >= 1, got {robots}")
    if time is not None and not time > 0:
        raise fail(f"--time: expected a positive number of simulated seconds, got {time}")
    if robot_logs not in ("auto", "on", "off"):
        raise fail(f"--robot-logs: expected auto, on or off, got {robot_logs!r}")
    from mimics.interfaces.live_view import VIEW_CHOICES, make_live_view

    if video is not None:
        from mimics.interfaces.replay import VIDEO_SUFFIXES

        if video.suffix.lower() not in VIDEO_SUFFIXES:  # checked before the run, not after
            raise fail(f"--video {video}: expected a file ending in {', '.join(VIDEO_SUFFIXES)}")
    if view not in VIEW_CHOICES:
        raise fail(f"--view: expected one of {', '.join(VIEW_CHOICES)}, got {view!r}")
    live = make_live_view(view)
    from mimics.interfaces.cli.first_run import kernels_compiled_ahead

    with kernels_compiled_ahead():
        try:
            params = parse_params(param or [])
            sim = prepare(scenario, algorithm, robots=robots, time=time, seed=seed,
                          policy=policy,  # type: ignore[arg-type]
                          wall_limit=wall_limit, params=params,
                          observers=(live,) if live is not None else (),
                          allow_overlap=allow_overlap)
        except MimicsError as exc:
            raise fail(str(exc)) from None
        if allow_overlap:
            from mimics.world.start_state import validate_scenario

            kept = validate_scenario(sim.scenario, f"scenario {sim.scenario.name!r}",
                                     allow_overlap=True)
            if kept:
                note(f"mimics: kept on purpose (--allow-overlap): {len(kept)} start "
                     f"problem(s), first: {kept[0]}")
        folder = out or Path("runs") / f"{sim.scenario.name}-{sim.controller.name}-s{seed}"
        result = run_to_folder(sim, folder, robot_logs=robot_logs, record_scans=record_scans)
    print_summary(result.summary(), folder)
    if video is not None:
        export_video(folder, video)
    if result.status == "error":
        raise typer.Exit(EXIT_FAILED)


def export_video(folder: Path, video: Path) -> None:
    """``--video``: the finished run's replay as a video file (exit 2 if it cannot be made)."""
    from mimics.interfaces.replay import export_replay

    try:
        export_replay(folder, video=video)
    except MimicsError as exc:
        raise fail(str(exc)) from None


@list_app.command("algorithms")
def list_algorithms_command() -> None:
    """Built-in algorithms, with a one-line description each."""
    from mimics.catalog import list_algorithms

    _print_catalog("algorithm", list_algorithms())


@list_app.command("scenarios")
def list_scenarios_command() -> None:
    """Built-in scenarios, with a one-line description each."""
    from mimics.catalog import list_scenarios

    _print_catalog("scenario", list_scenarios())


def _print_catalog(kind: str, entries: list[tuple[str, str]]) -> None:
    table = Table(show_header=True)
    table.add_column(kind)
    table.add_column("description")
    for name, description in entries:
        table.add_row(name, description)
    console.print(table)


def _mount_subcommands() -> None:
    from mimics.interfaces.cli.battery import app as battery_app
    from mimics.interfaces.cli.battery_report import report_command as battery_report
    from mimics.interfaces.cli.export import export_command
    from mimics.interfaces.cli.maps import app as map_app
    from mimics.interfaces.cli.maps import data_app
    from mimics.interfaces.cli.native import include_dir_command
    from mimics.interfaces.cli.records import logs_app, report_command
    from mimics.interfaces.cli.robots import list_robots_command, robot_app
    from mimics.interfaces.cli.ros import ros_command
    from mimics.interfaces.cli.ui import ui_command
    from mimics.interfaces.cli.view import battery_plot_command, plot_command, replay_command

    battery_app.command("report")(battery_report)
    battery_app.command("plot")(battery_plot_command)
    app.add_typer(battery_app, name="battery")
    app.add_typer(map_app, name="map")
    app.add_typer(data_app, name="data")
    app.add_typer(logs_app, name="logs")
    app.command("report")(report_command)
    app.command("replay")(replay_command)
    app.command("plot")(plot_command)
    app.add_typer(robot_app, name="robot")
    list_app.command("robots")(list_robots_command)
    app.command("ui")(ui_command)
    app.command("include-dir")(include_dir_command)
    app.command("ros")(ros_command)
    app.command("export")(export_command)


_mount_subcommands()


def main(argv: list[str] | None = None) -> int:
    """Entry point: runs the app and turns usage errors into one line and status 2."""
    command = _command()
    try:
        code = command.main(args=argv, prog_name="mimics", standalone_mode=False)
    except MimicsError as exc:
        fail(str(exc))
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        fail("interrupted")
        return EXIT_INTERRUPTED
    except (MemoryError, OverflowError, RecursionError) as exc:
        # Last resort: the specific checks (cli/values.py, mimics.world.limits,
        # mimics.records.resources) should have refused the input before this.
        fail(f"the input is too large for this machine or for the numbers it names "
             f"({type(exc).__name__}: {_first_line(exc)}); use smaller values")
        return EXIT_BAD_INPUT
    except UnicodeError as exc:  # a name from a non-UTF-8 file system, or a file's bytes
        fail(f"text that is not valid UTF-8 ({_first_line(exc)})")
        return EXIT_BAD_INPUT
    except OSError as exc:  # a path the system refuses (too long, a device, no permission)
        where = f"{exc.filename}: " if exc.filename else ""
        fail(f"{where}{exc.strerror or _first_line(exc)}")
        return EXIT_BAD_INPUT
    except ValueError as exc:
        if not _raised_by_numpy(exc):
            raise
        fail(f"a value NumPy cannot use ({_first_line(exc)})")
        return EXIT_BAD_INPUT
    except Exception as exc:
        # Typer vendors its own click: recognise its exceptions by their shape.
        name = type(exc).__name__
        if hasattr(exc, "exit_code") and name == "Exit":
            return int(exc.exit_code)  # type: ignore[attr-defined]
        if name.startswith("NoArgsIsHelp"):  # `mimics`, `mimics list`: no command given
            print(exc.format_message())  # type: ignore[attr-defined]  # the group's help
            return 0
        if name == "Abort":
            fail("interrupted")
            return 130
        if hasattr(exc, "format_message"):
            fail(exc.format_message())  # type: ignore[attr-defined]
            return 2
        raise
    return code if isinstance(code, int) else 0


@functools.cache
def _command() -> Any:
    """The click command of ``app``, built once per process (building it takes ~50 ms)."""
    return typer.main.get_command(app)


def _first_line(exc: BaseException) -> str:
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


def _raised_by_numpy(exc: BaseException) -> bool:
    """Whether the innermost frame of ``exc``'s traceback is in NumPy (or pandas, pyarrow)."""
    tb = exc.__traceback__
    while tb is not None and tb.tb_next is not None:
        tb = tb.tb_next
    name = tb.tb_frame.f_globals.get("__name__", "") if tb is not None else ""
    return name.split(".")[0] in ("numpy", "pandas", "pyarrow")


if __name__ == "__main__":
    sys.exit(main())
