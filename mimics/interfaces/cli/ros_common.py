"""What `mimics ros` (cli/ros.py) and `mimics ros2` (cli/ros2.py) share: their common
options, one definition each, the checks of those options, and how a bridge run's
inputs are read and its end reported."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer

from mimics.interfaces.cli.output import fail
from mimics.world.errors import MimicsError

if TYPE_CHECKING:
    from mimics.engine.outcome import RunResult
    from mimics.interfaces.ros.stopping import StopRequest

Robots = Annotated[int | None, typer.Option(help="Number of robots (scenario parameter).")]
Lockstep = Annotated[bool | None, typer.Option(
    "--lockstep/--realtime",
    help="Lockstep: each step waits for every active robot's command (deterministic). "
         "Realtime: wall-clock pace, the last command received, as stage_ros runs. "
         "[default: lockstep; realtime with --names stage]")]
StrictLockstep = Annotated[bool, typer.Option(
    "--strict-lockstep", help="Lockstep with no grace: every step waits for every "
                              "robot's command, up to --timeout.")]
Grace = Annotated[float, typer.Option(
    help="Lockstep: seconds a step waits for a robot whose node skips it (it sent a "
         "command within --timeout) before the robot holds its last command.")]
StartupGrace = Annotated[float, typer.Option(
    help="Seconds from the start to wait for the nodes' further subscriptions (a late "
         "scan subscriber gets step 0's scan); realtime: the longest wait for the "
         "nodes before the clock starts.")]
SimulatedTime = Annotated[float | None, typer.Option(help="Simulated seconds to run.")]
Seed = Annotated[int, typer.Option(help="Seed of every random draw.")]
Timeout = Annotated[float, typer.Option(
    help="Seconds to wait for the controller nodes to connect and, in lockstep, for "
         "all of each step's commands (one deadline per step).")]
MapResolution = Annotated[float, typer.Option(help="Metres per cell of /map.")]
RobotLogs = Annotated[str, typer.Option(help="Per-robot text logs: auto, on or off.")]
Params = Annotated[list[str] | None, typer.Option(
    "--param", help="Scenario parameter NAME=VALUE (repeatable), as for mimics run.")]
RecordScans = Annotated[bool, typer.Option(
    "--record-scans", help="Also record the laser scans (scans.parquet, 1 mm steps).")]
PublishMapOdom = Annotated[bool | None, typer.Option(
    "--publish-map-odom/--no-publish-map-odom",
    help="Publish each robot's map -> odom on /tf (the correction that puts it at its "
         "measured pose in map). stage_ros publishes none: it would fight a localiser "
         "such as amcl. [default: on; off with --names stage]")]
Names = Annotated[str, typer.Option(
    help="Topic and frame names: mimics, or stage for stage_ros' names (odom, "
         "base_scan, base_pose_ground_truth, cmd_vel; no robot_i/ prefix for one "
         "robot).")]


def check_bridge_arguments(*, lockstep: bool | None, strict_lockstep: bool, names: str,
                           robots: int | None, time: float | None, timeout: float,
                           grace: float, startup_grace: float, watchdog: float,
                           map_resolution: float, robot_logs: str,
                           publish_map_odom: bool | None) -> dict[str, Any]:
    """Check the options both bridges share; returns the fields of the run's
    :class:`~mimics.interfaces.ros.bridge_core.BridgeOptions` (built once the compiles
    have started, see :func:`run_bridge`).

    Raises:
        typer.Exit: status 2, after one line naming the option and what was expected.
    """
    if lockstep is None:  # stage_ros' habit: the clock runs, commands apply when they come
        lockstep = strict_lockstep or names != "stage"
    if strict_lockstep and not lockstep:
        raise fail("--strict-lockstep: a lockstep option; it cannot go with --realtime")
    if robots is not None and robots < 1:
        raise fail(f"--robots: expected a whole number >= 1, got {robots}")
    if time is not None and not time > 0:
        raise fail(f"--time: expected a positive number of simulated seconds, got {time}")
    if not timeout > 0:
        raise fail(f"--timeout: expected a positive number of seconds, got {timeout}")
    if not grace > 0:
        raise fail(f"--grace: expected a positive number of seconds, got {grace}")
    if not startup_grace >= 0:
        raise fail(f"--startup-grace: expected a number of seconds >= 0, got {startup_grace}")
    if not watchdog > 0:
        raise fail(f"--watchdog: expected a positive number of seconds, got {watchdog}")
    if not map_resolution > 0:
        raise fail(f"--map-resolution: expected a positive number of metres, "
                   f"got {map_resolution}")
    if robot_logs not in ("auto", "on", "off"):
        raise fail(f"--robot-logs: expected auto, on or off, got {robot_logs!r}")
    return {"lockstep": lockstep, "timeout": timeout, "map_resolution": map_resolution,
            "watchdog": watchdog, "names": names,
            "grace": None if strict_lockstep else grace, "startup_grace": startup_grace,
            "publish_map_odom": publish_map_odom}


View = Annotated[str, typer.Option(help="Live view: step, 1s, 10s or off.")]
Video = Annotated[Path | None, typer.Option(help="Also export a video of the run.")]
Watchdog = Annotated[float, typer.Option(
    help="Realtime: stop a robot whose commands stop for this many simulated seconds "
         "(stage_ros' base_watchdog_timeout; under mimics ros the private parameter "
         "_base_watchdog_timeout:=S sets it too).")]


def run_inputs(scenario: str, *, names: str, param: list[str] | None, robots: int | None,
               time: float | None, out: Path | None, view: str) -> dict[str, Any]:
    """The scenario parameters of a bridge run, after checking the name set, the
    parameters, ``--out`` and ``--view``.

    Raises:
        typer.Exit: status 2, after one line naming the option and what was expected.
    """
    from mimics.interfaces.cli.run_summary import check_repeated, parse_params
    from mimics.interfaces.live_view import VIEW_CHOICES
    from mimics.interfaces.ros.names import check_name_set

    if view not in VIEW_CHOICES:
        raise fail(f"--view: expected one of {', '.join(VIEW_CHOICES)}, got {view!r}")
    try:
        check_name_set(names, "--names")
        params = parse_params(param or [])
        check_repeated(params, robots=robots, time=time)
        if out is not None:  # an earlier run there is replaced, the scenario file never
            from mimics.records.layout import check_run_output

            scenario_file = Path(scenario) if scenario.endswith((".py", ".toml")) else None
            check_run_output("--out", out, {"the scenario file": scenario_file})
    except MimicsError as exc:
        raise fail(str(exc)) from None
    if robots is not None:
        params["robots"] = robots
    return params


def run_bridge(scenario: str, tag: str, load_runner: Callable[[], Callable[..., RunResult]],
               options: dict[str, Any], *, out: Path | None, seed: int, view: str,
               video: Path | None, **run_args: Any) -> None:
    """Run a bridge and report its end, as both commands do: the first run's compiles
    started before Numba is imported, the live view, a new run folder, SIGINT and SIGTERM
    at a step boundary.

    Args:
        tag: the run folder's middle name (``runs/SCENARIO-TAG-sSEED``).
        load_runner: imports and returns the bridge's run function (``run_ros``...),
            called once the compiles have started.
        options: :func:`check_bridge_arguments`' fields of the bridge's options.
        run_args: passed on to the run function (params, time, robot_logs...).
    """
    from mimics.interfaces.cli.compiling.first_run import compiles_started, kernels_compiled_ahead

    with compiles_started():  # a fresh install's compiles start before Numba is imported
        from mimics.interfaces.live_view import make_live_view
        from mimics.interfaces.ros.bridge_core import BridgeOptions
        from mimics.interfaces.ros.stopping import RunInterrupted, StopRequest, exit_status
        from mimics.records.naming import new_run_folder

        run = load_runner()
        live = make_live_view(view)
    stop = StopRequest()  # SIGINT, SIGTERM: the run ends at a step boundary
    try:
        # the default name, never one taken (-2, -3...): a run never replaces another;
        # absolute, so that the message says where it is (roslaunch runs us in $ROS_HOME)
        folder = out or new_run_folder("runs", Path(scenario).stem, tag, seed).absolute()
        folders: list[Path] = []  # more than one after a reset (/mimics/reset)
        with kernels_compiled_ahead():
            result = run(scenario, folder, options=BridgeOptions(**options), seed=seed,
                         observers=(live,) if live is not None else (), folders=folders,
                         stop=stop, **run_args)
    except RunInterrupted as exc:
        fail(str(exc))
        raise typer.Exit(exit_status(exc.signum)) from None
    except MimicsError as exc:
        raise fail(str(exc)) from None
    report_end(result, folder, folders, video, stop)


def report_end(result: RunResult, folder: Path, folders: list[Path], video: Path | None,
               stop: StopRequest) -> None:
    """The runs a reset ended, the summary, the video; exit 1 after a lockstep time-out,
    the shell's status of a signal after SIGINT or SIGTERM."""
    from mimics.interfaces.cli.run_summary import export_video, print_summary
    from mimics.interfaces.ros.stopping import exit_status

    for earlier in folders[:-1]:
        print(f"reset: the run in {earlier} ended (status stopped) and started again")
    folder = folders[-1] if folders else folder
    print_summary(result.summary(), folder)
    if video is not None:
        export_video(folder, video)
    if result.status == "error" and "LockstepTimeout" in result.error:
        fail(result.error)
        raise typer.Exit(1)
    if stop.signum is not None:  # the shell's status of a process a signal ended
        raise typer.Exit(exit_status(stop.signum))
