"""``mimics run``: one simulation, its summary and its run folder.

A C or C++ algorithm runs in a child process (:mod:`mimics.interfaces.cli.native`);
the child calls :func:`child_main`, which runs this same command.
"""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path
from typing import Annotated

import typer

from mimics.interfaces.cli.output import EXIT_FAILED, fail, note
from mimics.interfaces.cli.run_summary import (
    check_repeated,
    export_video,
    parse_params,
    print_summary,
)
from mimics.world.errors import MimicsError


def run(
    scenario: Annotated[str, typer.Argument(help="Built-in scenario name or a .py/.toml file.")],
    algorithm: Annotated[str, typer.Argument(help="Built-in algorithm name or a .py, .c or "
                                                  ".cpp file.")],
    robots: Annotated[int | None, typer.Option(help="Number of robots (scenario parameter).")]
    = None,
    time: Annotated[float | None, typer.Option(help="Simulated seconds to run.")] = None,
    seed: Annotated[int, typer.Option(help="Seed of every random draw.")] = 0,
    out: Annotated[Path | None, typer.Option(
        help="Run folder [default: runs/SCENARIO-ALGO-sSEED, or -2, -3... when taken]")] = None,
    policy: Annotated[str, typer.Option(help="On user exceptions: abort or deactivate.")]
    = "abort",
    param: Annotated[list[str] | None, typer.Option(help="Scenario parameter NAME=VALUE "
                                                         "(repeatable).")] = None,
    wall_limit: Annotated[float | None, typer.Option(
        help="Stop after this many wall seconds, also inside a step that does not return "
             "(exit 1).")] = None,
    robot_logs: Annotated[str, typer.Option(help="Per-robot text logs: auto, on or off.")]
    = "auto",
    view: Annotated[str, typer.Option(help="Live view: step, 1s, 10s or off.")] = "off",
    video: Annotated[Path | None, typer.Option(help="Also export a video of the run.")] = None,
    record_scans: Annotated[bool, typer.Option("--record-scans", help="Also record the laser "
                                               "scans (scans.parquet, 1 mm steps).")] = False,
    allow_overlap: Annotated[bool, typer.Option(
        help="Keep robots that start touching a wall or each other, or outside the map "
             "(reported, then run).")] = False,
    ros_timeout: Annotated[float | None, typer.Option(
        help="ros: and ros2: algorithms: seconds to wait for the node to connect and, each "
             "step, for all its commands [default: 10]")] = None,
    ros_names: Annotated[str | None, typer.Option(
        help="ros: and ros2: algorithms: topic and frame names, mimics or stage (stage_ros' names) "
             "[default: mimics]")] = None,
) -> None:
    """Run one simulation, print its summary and write its run folder.

    Exit status 0 when the run ended by its end criteria, 1 when it ended in
    error (user code raised under --policy abort, or a step still running at
    --wall-limit was stopped), 2 for bad input.
    """
    from mimics.interfaces.cli.native import needs_child, run_in_child

    if needs_child(algorithm):  # compiled code may crash: run it in a child process
        raise typer.Exit(run_in_child(dict(
            scenario=scenario, algorithm=algorithm, robots=robots, time=time, seed=seed,
            out=out, policy=policy, param=param, wall_limit=wall_limit, robot_logs=robot_logs,
            view=view, video=video, record_scans=record_scans, allow_overlap=allow_overlap,
            ros_timeout=ros_timeout, ros_names=ros_names)))
    if policy not in ("abort", "deactivate"):
        raise fail(f"--policy: expected abort or deactivate, got {policy!r}")
    if robots is not None and robots < 1:
        raise fail(f"--robots: expected a whole number >= 1, got {robots}")
    if time is not None and not time > 0:
        raise fail(f"--time: expected a positive number of simulated seconds, got {time}")
    if robot_logs not in ("auto", "on", "off"):
        raise fail(f"--robot-logs: expected auto, on or off, got {robot_logs!r}")
    if ros_timeout is not None and not ros_timeout > 0:
        raise fail(f"--ros-timeout: expected a positive number of seconds, got {ros_timeout}")
    if algorithm.startswith(("ros:", "ros2:")):  # one DEFAULTS for both
        from mimics.interfaces.ros.node_algorithm import DEFAULTS

        DEFAULTS.timeout_option = "--ros-timeout"
        if ros_timeout is not None:
            DEFAULTS.timeout = ros_timeout
        if ros_names is not None:
            from mimics.interfaces.ros.names import check_name_set

            try:
                DEFAULTS.names = check_name_set(ros_names, "--ros-names")
            except MimicsError as exc:
                raise fail(str(exc)) from None
    elif ros_timeout is not None or ros_names is not None:
        option = "--ros-timeout" if ros_timeout is not None else "--ros-names"
        raise fail(f"{option}: only for ros: and ros2: algorithms "
                   "(ros:PROGRAM or ros2:PROGRAM [ARGS...])")
    from mimics.interfaces.cli.compiling.first_run import compiles_started, kernels_compiled_ahead

    with compiles_started():  # a fresh install's compiles start before Numba is imported
        from mimics.interfaces.live_view import VIEW_CHOICES, make_live_view
        from mimics.records.layout import check_run_output
        from mimics.records.naming import new_run_folder
        from mimics.records.runner import prepare, run_to_folder

        if video is not None:
            from mimics.interfaces.replay import VIDEO_SUFFIXES
            from mimics.interfaces.replay.export import require_ffmpeg

            require_ffmpeg()  # before the run, not after
            if video.suffix.lower() not in VIDEO_SUFFIXES:  # checked before the run, not after
                raise fail(f"--video {video}: expected a file ending in "
                           f"{', '.join(VIDEO_SUFFIXES)}")
        if view not in VIEW_CHOICES:
            raise fail(f"--view: expected one of {', '.join(VIEW_CHOICES)}, got {view!r}")
        live = make_live_view(view)
    with kernels_compiled_ahead():
        try:
            if out is not None:  # an earlier run there is replaced, a file the run reads never
                check_run_output("--out", out, {"the scenario file": _file(scenario),
                                                "the algorithm file": _file(algorithm)})
            params = parse_params(param or [])
            check_repeated(params, robots=robots, time=time)
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
        if out is not None:  # the folder the user named: an earlier run in it is replaced
            folder = out
        else:  # the default name, never one taken: -2, -3... ("records in" says which)
            try:
                folder = new_run_folder("runs", sim.scenario.name, sim.controller.name, seed)
            except MimicsError as exc:
                raise fail(str(exc)) from None
        result = run_to_folder(sim, folder, robot_logs=robot_logs, record_scans=record_scans)
    print_summary(result.summary(), folder)
    if video is not None:
        export_video(folder, video)
    if result.status == "error" or result.error:  # an error, or a step stopped at the limit
        raise typer.Exit(EXIT_FAILED)


def _file(name: str) -> Path | None:
    """The file a scenario or algorithm argument names (None: a built-in name)."""
    return Path(name) if Path(name).is_file() else None


def child_main() -> None:
    """In the child of a C/C++ run: run the command with the arguments the parent passed."""
    from mimics.interfaces.cli.native import CHILD_ENV

    arguments = json.loads(os.environ[CHILD_ENV])
    for key in ("out", "video"):
        if arguments.get(key) is not None:
            arguments[key] = Path(arguments[key])
    try:
        run(**arguments)
    except KeyboardInterrupt:
        fail("interrupted")
        sys.exit(130)
    except MimicsError as exc:
        fail(str(exc))
        sys.exit(2)
    except Exception as exc:
        if type(exc).__name__ == "Exit" and hasattr(exc, "exit_code"):  # typer.Exit
            sys.exit(int(exc.exit_code))
        raise
    sys.exit(0)
