"""The ``mimics`` command line.

Every error a user can cause (an unknown name, a bad number, a malformed file)
is printed as one line on stderr and exits with status 2.
"""

from __future__ import annotations

import functools
import sys
from typing import Any

import typer
from rich.console import Console
from rich.table import Table

from mimics.interfaces.cli.output import (
    EXIT_BAD_INPUT,
    EXIT_INTERRUPTED,
    fail,
)
from mimics.interfaces.cli.values import guard_values
from mimics.world.errors import MimicsError

HELP = """mimics: a fast multi-robot simulator for teaching, prototyping and batteries.

\b
Exit status (every command):
  0    done as asked: a run ended by its end criteria (all robots finished,
       time or wall-clock limit, stop predicate), whatever its collisions;
       a battery whose runs all finished, whatever their outcomes
  1    it ran, but failed: a run ended in error (user code raised under
       --policy abort, or a step that did not return was stopped at
       --wall-limit); battery runs that could not finish (error, timeout,
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


@app.callback()
def root(ctx: typer.Context) -> None:
    """Check every number and text given to any command before it runs (cli/values.py)."""
    guard_values(ctx.find_root().command)


@list_app.command("algorithms")
def list_algorithms_command() -> None:
    """Built-in algorithms, with a one-line description each."""
    from mimics.catalog import list_algorithms

    _print_catalog("algorithm", list_algorithms())


@list_app.command("scenarios")
def list_scenarios_command() -> None:
    """Built-in scenarios: a one-line description each, and what the run's seed changes."""
    from mimics.catalog import list_scenarios, scenario_seed_changes

    table = Table(show_header=True, caption="Every seed also changes the sensors' noise (off "
                                            "with --param noise=off).")
    table.add_column("scenario")
    table.add_column("description")
    table.add_column("the seed changes")
    for name, description in list_scenarios():
        table.add_row(name, description, scenario_seed_changes(name))
    console.print(table)


def _print_catalog(kind: str, entries: list[tuple[str, str]]) -> None:
    table = Table(show_header=True)
    table.add_column(kind)
    table.add_column("description")
    for name, description in entries:
        table.add_row(name, description)
    console.print(table)


def _mount_subcommands() -> None:
    from mimics.interfaces.cli.battery import app as battery_app
    from mimics.interfaces.cli.battery_report import compare_command as battery_compare
    from mimics.interfaces.cli.battery_report import report_command as battery_report
    from mimics.interfaces.cli.export import export_command
    from mimics.interfaces.cli.maps import app as map_app
    from mimics.interfaces.cli.maps import data_app
    from mimics.interfaces.cli.native import include_dir_command
    from mimics.interfaces.cli.records import logs_app, report_command
    from mimics.interfaces.cli.robots import list_robots_command, robot_app
    from mimics.interfaces.cli.ros import ros_command, ros_files_command
    from mimics.interfaces.cli.ros2 import ros2_command
    from mimics.interfaces.cli.single_run import run
    from mimics.interfaces.cli.ui import ui_command
    from mimics.interfaces.cli.view import battery_plot_command, plot_command, replay_command

    app.command("run")(run)
    battery_app.command("report")(battery_report)
    battery_app.command("compare")(battery_compare)
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
    app.command("ros2")(ros2_command)
    app.command("ros-files")(ros_files_command)
    app.command("export")(export_command)


_mount_subcommands()


def main(argv: list[str] | None = None) -> int:
    """Entry point: runs the app and turns usage errors into one line and status 2."""
    command = _command(_first_word(sys.argv[1:] if argv is None else argv))
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
def _command(word: str | None = None) -> Any:
    """The click command of ``app``, built once per process (building it takes 25-50 ms).

    When ``word`` names one of the app's own commands (``run``, ``report``...),
    only that command is built under the app's root: what it parses, its help,
    its checks (``guard_values``) and its errors are those of the whole app, and
    the other commands, which the process will not run, are not built.
    """
    chosen = [info for info in app.registered_commands if word is not None
              and (info.name or getattr(info.callback, "__name__", "")) == word]
    if len(chosen) != 1:
        return typer.main.get_command(app)
    alone = typer.Typer(name=app.info.name, help=app.info.help,
                        no_args_is_help=app.info.no_args_is_help, add_completion=False,
                        pretty_exceptions_enable=False, rich_markup_mode=None)
    alone.registered_callback = app.registered_callback
    alone.registered_commands = chosen
    return typer.main.get_command(alone)


def _first_word(args: list[str]) -> str | None:
    """The command named first on the command line (None: an option or nothing first)."""
    return args[0] if args and not args[0].startswith("-") else None


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
