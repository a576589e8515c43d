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
    mimics battery rerun-failed batteries/night1
    mimics battery report batteries/night1 [--csv out.csv] [--parquet out.parquet]
    mimics battery compare batteries/night1 [--baseline ALGO] [--metric M ...] [--csv out.csv]
    mimics battery run battery.toml --until time_to_goal:0.2   # seeds until the answer is known
"""

from __future__ import annotations

import os
import sys
import time
import tomllib
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from mimics.interfaces.cli.battery_args import Folder, table_console
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
def _interrupted(folder: Path) -> typer.Exit:
    Console(stderr=True, highlight=False).print(
        f"interrupted: finished runs are kept; go on with `mimics battery resume {folder}`",
        markup=False)
    return typer.Exit(130)


# -- new -----------------------------------------------------------------------------

@app.command()
def new(
    output: Annotated[Path, typer.Option("--output", "-o", help="The battery file to write.")]
    = Path("battery.toml"),
    algorithm: Annotated[list[str] | None, typer.Option(
        "--algorithm", "-a", help="A built-in algorithm or a .py file (repeatable).")] = None,
    scenario: Annotated[list[str] | None, typer.Option(
        "--scenario", "-s", help="A built-in scenario or a .py/.toml file (repeatable).")] = None,
    param: Annotated[list[str] | None, typer.Option(
        "--param", "-p", help="Scenario parameter NAME=V1,V2,... (a sweep) or "
                              "SCENARIO.NAME=...; repeatable.")] = None,
    seeds: Annotated[str | None, typer.Option(
        help="A count (30: seeds 1..30) or a list (1,5,9) [default: 30].")] = None,
    time_: Annotated[float | None, typer.Option(
        "--time", help="Simulated seconds per run [default: each scenario's].")] = None,
    timeout: Annotated[float | None, typer.Option(
        help="Wall-clock seconds per run before it is stopped [default: 300].")] = None,
    policy: Annotated[str | None, typer.Option(
        help="On exceptions in user code: abort (the run) or deactivate (the robot).")] = None,
    robot_logs: Annotated[str, typer.Option(
        help="Per-robot text logs in run folders: off, auto or on.")] = "off",
    no_input: Annotated[bool, typer.Option(
        "--no-input", help="Never prompt (also when stdin is not a terminal).")] = False,
    force: Annotated[bool, typer.Option(help="Overwrite an existing battery file.")] = False,
) -> None:
    """Set up a battery: pick algorithms and scenarios from lists, seeds and settings.

    Prompts for what the options do not give (when on a terminal); saves the
    battery file and remembers it for `mimics battery run --last`.
    """
    from mimics.batteries.config import remember_battery
    from mimics.batteries.spec import battery_toml, spec_from_dict

    interactive = not no_input and stdin_is_terminal()
    try:
        if output.exists() and not force and not (
                interactive and typer.confirm(f"{output} exists: overwrite it?", default=False)):
            raise MimicsError(f"{output} exists (use --force to overwrite it)")
        algorithms = list(algorithm or []) or (_pick("algorithm") if interactive else [])
        scenarios = list(scenario or []) or (_pick("scenario") if interactive else [])
        if not algorithms:
            raise MimicsError("no algorithm: give --algorithm NAME (repeatable)")
        if not scenarios:
            raise MimicsError("no scenario: give --scenario NAME (repeatable)")
        tables = _scenario_tables(scenarios, param or [], interactive)
        if interactive:
            seeds = seeds or typer.prompt("Seeds: a count or a list", default="30")
            if time_ is None:
                text = typer.prompt("Simulated seconds per run (empty: each scenario's)",
                                    default="", show_default=False)
                time_ = float(text) if text.strip() else None
            timeout = timeout or float(typer.prompt("Wall-clock timeout per run (s)",
                                                    default="300"))
            policy = policy or typer.prompt("On exceptions in user code: abort or deactivate",
                                            default="abort")
        text = battery_toml([_relative(a, output) for a in algorithms], tables,
                            seeds=_parse_seeds(seeds or "30"), time=time_,
                            timeout=timeout or 300.0, policy=policy or "abort",
                            robot_logs=robot_logs)
        spec = spec_from_dict(tomllib.loads(text), base=output.parent.resolve(),
                              source=str(output))
        output.parent.mkdir(parents=True, exist_ok=True)
        output.write_text(text)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    except (ValueError, OSError) as exc:  # a bad number typed at a prompt, an unwritable file
        raise _fail(f"{type(exc).__name__}: {exc}") from None
    remember_battery(output)
    runs = len(spec.runs())
    table_console().print(f"saved {output}: {runs} runs ({len(spec.algorithms)} algorithm(s) x "
                 f"{len(spec.scenarios)} scenario(s) x {len(spec.seeds)} seed(s) with sweeps); "
                 f"run it with `mimics battery run {output} --out batteries/{output.stem}`",
                 markup=False)


def stdin_is_terminal() -> bool:
    """Whether prompts can be answered (stdin is a terminal)."""
    return sys.stdin.isatty()


def _pick(kind: str) -> list[str]:
    from mimics.catalog import list_algorithms, list_scenarios

    entries = list_algorithms() if kind == "algorithm" else list_scenarios()
    table = Table(title=f"{kind}s", show_header=True)
    table.add_column("#", justify="right")
    table.add_column(kind)
    table.add_column("description")
    for k, (name, description) in enumerate(entries, start=1):
        table.add_row(str(k), name, description)
    table_console().print(table)
    answer = typer.prompt(f"{kind.capitalize()}s: numbers, names or paths, comma-separated")
    chosen = []
    for item in (a.strip() for a in answer.split(",")):
        if item.isdigit() and 1 <= int(item) <= len(entries):
            chosen.append(entries[int(item) - 1][0])
        elif item:
            chosen.append(item)
    return chosen


def _values(text: str) -> Any:
    """``"1,10,60"`` -> [1, 10, 60]; ``"2.5"`` -> 2.5; bare words are strings."""
    try:
        values = tomllib.loads(f"v = [{text}]")["v"]
    except tomllib.TOMLDecodeError:
        values = [v.strip() for v in text.split(",")]
    return values[0] if len(values) == 1 else values


def _scenario_tables(scenarios: list[str], params: list[str], interactive: bool
                     ) -> list[dict[str, Any]]:
    from mimics.catalog import scenario_parameters

    tables: list[dict[str, Any]] = [{"name": s} for s in scenarios]
    for item in params:
        key, sep, text = item.partition("=")
        if not sep or not key.strip() or not text.strip():
            raise MimicsError(f"--param {item!r}: expected NAME=V1,V2 or SCENARIO.NAME=V1,V2")
        where, dot, name = key.strip().rpartition(".")
        targets = [t for t in tables if not dot or t["name"] == where]
        if dot and not targets:
            raise MimicsError(f"--param {item!r}: no scenario {where!r} was chosen")
        if not dot:
            targets = [t for t in targets if name in _parameters_of(t["name"])]
            if not targets:
                raise MimicsError(f"--param {item!r}: no chosen scenario has a parameter "
                                  f"{name!r}")
        for table in targets:
            table[name] = _values(text.strip())
    if interactive:
        for table in tables:
            if len(table) > 1:
                continue
            defaults = scenario_parameters(table["name"]) if not table["name"].endswith(
                ".toml") else {}
            shown = ", ".join(f"{k}={v}" for k, v in defaults.items()) or "robots, seed"
            answer = typer.prompt(f"Parameters of {table['name']} ({shown}) as NAME=V1,V2; "
                                  "empty for the defaults", default="", show_default=False)
            for part in filter(None, (p.strip() for p in answer.split(";"))):
                key, sep, text = part.partition("=")
                if not sep:
                    raise MimicsError(f"{part!r}: expected NAME=V1,V2")
                table[key.strip()] = _values(text.strip())
    return tables


def _parameters_of(scenario: str) -> dict[str, Any]:
    from mimics.catalog import scenario_parameters

    if scenario.endswith(".toml"):
        from mimics.world.scenario_files import SWEEPABLE

        return dict.fromkeys(SWEEPABLE)
    return scenario_parameters(scenario)


def _parse_seeds(text: str) -> int | list[int]:
    parts = [p.strip() for p in text.split(",") if p.strip()]
    if not parts or not all(p.isdigit() for p in parts):
        raise MimicsError(f"--seeds {text!r}: expected a count (30) or a list (1,5,9)")
    return int(parts[0]) if len(parts) == 1 and "," not in text else [int(p) for p in parts]


def _relative(name: str, output: Path) -> str:
    """A path given on the command line, relative to the battery file's folder."""
    from mimics.batteries.references import is_path, resolve_algorithm
    from mimics.catalog import algorithm_scheme

    if algorithm_scheme(name) is not None:  # its program from the current folder, absolute
        return resolve_algorithm(name, Path.cwd())
    if not is_path(name):
        return name
    try:
        return os.path.relpath(Path(name).resolve(), output.parent.resolve())
    except ValueError:  # another drive (Windows)
        return str(Path(name).resolve())


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
             "min_seeds and max_seeds from the file's table, else 10 and 500).")] = None,
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
        folder = out or Path("batteries") / f"{path.stem}-{time.strftime('%Y%m%d-%H%M%S')}"
        remember_battery(path)
        _announce(folder, len(spec.runs()), workers, dask, spec.until is not None)
        result = run_battery(spec, folder, workers=workers, dask=dask, progress=progress)
    except MimicsError as exc:
        raise _fail(str(exc)) from None
    except KeyboardInterrupt:
        raise _interrupted(folder) from None
    _finished(result)


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
        raise _interrupted(folder) from None
    _finished(result)


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
        raise _interrupted(folder) from None
    _finished(result)


def _announce(folder: Path, runs: int, workers: int | None, dask: str | None,
              rounds: bool = False) -> None:
    where = f"the Dask cluster at {dask}" if dask else \
        f"{min(workers or os.cpu_count() or 1, runs)} local worker(s)"
    Console(stderr=True, highlight=False).print(
        f"battery {folder}: {runs} runs{' in the first round' if rounds else ''} on {where}",
        markup=False)


def _finished(result: Any) -> None:
    table_console().print(result.line(), markup=False)
    from mimics.interfaces.cli.battery_report import print_warnings

    print_warnings(result.folder)
    if result.adopted:
        table_console().print(f"({result.adopted} run(s) had finished just before the battery "
                              "stopped: kept)", markup=False)
    table_console().print(f"table: `mimics battery report {result.folder}`", markup=False)
    from mimics.batteries.tasks import FAILED_STATES

    failed = {state: result.counts.get(state, 0) for state in FAILED_STATES
              if result.counts.get(state, 0)}
    if failed:
        total = sum(result.counts.values())
        states = ", ".join(f"{n} {state}" for state, n in failed.items())
        # Running again helps only what the machine caused: a run's own exception
        # (state error) repeats with the same seed, so it is not suggested for those.
        again = [state for state in ("timeout", "crashed") if state in failed]
        advice = (f"; runs that timed out or crashed may finish when run again: `mimics "
                  f"battery rerun-failed {result.folder} "
                  + " ".join(f"--state {state}" for state in again) + "`" if again else "")
        if "error" in failed:
            advice += ("; an error is the algorithm's own exception and repeats with the same "
                       "seed: fix the code, then run the battery again")
        Console(stderr=True, highlight=False, soft_wrap=True).print(
            f"mimics: {sum(failed.values())} of {total} runs could not finish ({states}): see "
            f"`mimics battery status {result.folder}`{advice}", markup=False)
        raise typer.Exit(1)  # exit status 1: some runs could not run (`mimics --help`)


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

