"""`mimics battery new`: write a battery file from options, or by asking on a terminal.

    mimics battery new -a go_to_goal -s line -p robots=1,10 --seeds 30
    mimics battery new -a go_to_goal -a wall_aware -s cave --until time_to_goal:0.5
    mimics battery new                     # asks for what the options do not give

Either a fixed number of seeds (``--seeds``) or the stopping rule
(``--until METRIC:HALF_WIDTH`` with ``--min-seeds`` and ``--max-seeds``: the
file's ``[battery.until]`` table, seeds 1, 2... in rounds per cell until the
95% interval of the metric's mean is narrow enough). On a terminal, the
question about seeds offers the rule first. Mounted on ``mimics battery`` by
``battery.py``.
"""

from __future__ import annotations

import os
import sys
import tomllib
from pathlib import Path
from typing import Annotated, Any

import typer
from rich.table import Table

from mimics.interfaces.cli.battery_args import table_console
from mimics.interfaces.cli.output import fail as _fail
from mimics.world.errors import MimicsError


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
    until: Annotated[str | None, typer.Option(
        help="METRIC:HALF_WIDTH instead of --seeds: seeds 1, 2... in rounds per cell until "
             "the 95% interval of the metric's mean is at most HALF_WIDTH each side "
             "([battery.until]).")] = None,
    min_seeds: Annotated[int | None, typer.Option(
        help="With --until: the seeds of a cell's first round [default: 10].")] = None,
    max_seeds: Annotated[int | None, typer.Option(
        help="With --until: the seeds of a cell at most [default: 500].")] = None,
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
    """Set up a battery: pick algorithms and scenarios from lists, seeds or a stopping rule,
    and settings.

    Prompts for what the options do not give (when on a terminal); saves the
    battery file and remembers it for `mimics battery run --last`.
    """
    from mimics.batteries.config import remember_battery
    from mimics.batteries.spec import battery_toml, spec_from_dict

    interactive = not no_input and stdin_is_terminal()
    try:
        if output.is_dir():
            raise MimicsError(f"--output {output}: a folder (expected the path of a battery file)")
        if output.exists() and not force and not (
                interactive and typer.confirm(f"{output} exists: overwrite it?", default=False)):
            raise MimicsError(f"{output} exists (use --force to overwrite it)")
        if seeds is not None or not interactive:  # (else the prompt may still choose)
            _check_seed_options(seeds, until, min_seeds, max_seeds)
        algorithms = list(algorithm or []) or (_pick("algorithm") if interactive else [])
        scenarios = list(scenario or []) or (_pick("scenario") if interactive else [])
        if not algorithms:
            raise MimicsError("no algorithm: give --algorithm NAME (repeatable)")
        if not scenarios:
            raise MimicsError("no scenario: give --scenario NAME (repeatable)")
        _check_output(output, [*algorithms, *scenarios])
        tables = _scenario_tables(scenarios, param or [], interactive)
        if interactive:
            if seeds is None and until is None:
                until = _ask_until() or None
            if until is not None:
                if min_seeds is None:
                    from mimics.batteries.until import DEFAULT_MIN_SEEDS

                    min_seeds = typer.prompt("Seeds of a cell's first round",
                                             default=DEFAULT_MIN_SEEDS,
                                             type=int)
                if max_seeds is None:
                    max_seeds = typer.prompt("Seeds of a cell at most", default=500, type=int)
            else:
                _check_seed_options(seeds, until, min_seeds, max_seeds)
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
        if until is not None:
            text = _with_until(text, until, min_seeds, max_seeds)
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
    shape = (f"{len(spec.algorithms)} algorithm(s) x {len(spec.scenarios)} scenario(s) x "
             f"{len(spec.seeds)} seed(s) with sweeps")
    if spec.until is None:
        saved = f"{runs} runs ({shape})"
    else:
        rule = spec.until
        saved = (f"{runs} runs in the first round ({shape}), then seeds in rounds per cell "
                 f"until the 95% interval of {rule.metric}'s mean is at most "
                 f"{rule.half_width:g} each side, {rule.max_seeds} seeds a cell at most")
    table_console().print(f"saved {output}: {saved}; run it with `mimics battery run {output} "
                          f"--out batteries/{output.stem}`", markup=False)


def stdin_is_terminal() -> bool:
    """Whether prompts can be answered (stdin is a terminal)."""
    return sys.stdin.isatty()


def _check_seed_options(seeds: str | None, until: str | None, min_seeds: int | None,
                        max_seeds: int | None) -> None:
    """Seeds either fixed or by the stopping rule, and the rule's bounds only with it."""
    if seeds is not None and until is not None:
        raise MimicsError("--seeds: not with --until, which runs seeds 1, 2... in rounds "
                          "until the answer is known")
    if until is None:
        for name, value in (("--min-seeds", min_seeds), ("--max-seeds", max_seeds)):
            if value is not None:
                raise MimicsError(f"{name}: only with --until (a fixed battery runs --seeds)")


def _ask_until() -> str:
    """The stopping rule typed at the prompt, or "" for a fixed number of seeds."""
    from mimics.batteries.metrics import METRICS

    return str(typer.prompt(
        "Stop each cell when its answer is known? METRIC:HALF_WIDTH, e.g. time_to_goal:0.5 "
        f"(metrics: {', '.join(METRICS)}); empty for a fixed number of seeds",
        default="", show_default=False)).strip()


def _with_until(text: str, until: str, min_seeds: int | None, max_seeds: int | None) -> str:
    """The battery file's text with a ``[battery.until]`` table instead of its seeds."""
    import tomli_w

    from mimics.batteries.until import (
        DEFAULT_MAX_SEEDS,
        DEFAULT_MIN_SEEDS,
        UntilRule,
        parse_until_option,
    )

    bounds = UntilRule("", 1.0, DEFAULT_MIN_SEEDS if min_seeds is None else min_seeds,
                       DEFAULT_MAX_SEEDS if max_seeds is None else max_seeds)
    rule = parse_until_option(until, _named_seed_options, bounds)
    data = tomllib.loads(text)
    del data["battery"]["seeds"]
    data["battery"]["until"] = {"metric": rule.metric, "half_width": rule.half_width,
                                "min_seeds": rule.min_seeds, "max_seeds": rule.max_seeds}
    return tomli_w.dumps(data)


def _named_seed_options(message: str) -> MimicsError:
    """A stopping rule's error naming the option that gave the field."""
    for key in ("min_seeds", "max_seeds"):
        message = message.replace(f"--until {key}", f"--{key.replace('_', '-')}")
    return MimicsError(message)


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


def _check_output(output: Path, names: list[str]) -> None:
    """Refuse an --output that is a file the battery reads (``-a algo.py -o algo.py``), or a
    record of the run or battery folder it would be written in (even with --force)."""
    from mimics.interfaces.cli.battery_args import battery_records
    from mimics.records.layout import SCENARIO_TOML, SUMMARY_JSON, run_records
    from mimics.world.output_paths import check_outputs

    inputs: dict[str, Any] = {f"the file {name}": name for name in names if Path(name).is_file()}
    for folder in (output.parent, *output.parent.parents):
        if (folder / "battery.db").is_file():
            inputs["the battery folder"] = battery_records(folder)
        elif (folder / SUMMARY_JSON).is_file() or (folder / SCENARIO_TOML).is_file():
            inputs["the run folder"] = run_records(folder)
    check_outputs({"--output": output}, inputs)


def _parse_seeds(text: str) -> int | list[int]:
    parts = [p.strip() for p in text.split(",")]  # an empty item ("1,,5", "1,") is a typo
    if not all(p.isascii() and p.isdigit() for p in parts):  # (isdigit alone takes "²")
        raise MimicsError(f"--seeds {text!r}: expected a count (30) or a list (1,5,9) of whole "
                          f"numbers, without empty items")
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
