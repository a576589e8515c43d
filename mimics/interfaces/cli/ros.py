"""`mimics ros`: a simulation run as a ROS 1 node, driven by ROS controllers.

The main CLI registers it with ``app.command("ros")(ros_command)``. Bad
input, no ROS installed or no master reachable: one line on stderr, status
2. A run that a lockstep time-out ended: its summary, then one line on
stderr, status 1.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from mimics.interfaces.cli.output import fail
from mimics.world.errors import MimicsError

# The options `mimics ros` shares with `mimics ros2` (cli/ros2.py): one definition each.
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
                           map_resolution: float, robot_logs: str) -> bool:
    """Check the options both bridges share; returns whether the run is lockstep.

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
    return lockstep


def ros_command(
    scenario: Annotated[str, typer.Argument(help="Built-in scenario name or a .py/.toml file.")],
    ros_args: Annotated[list[str] | None, typer.Argument(
        metavar="[FROM:=TO]...",
        help="ROS arguments, as roslaunch passes them: remaps (base_scan:=scan), "
             "__name:=NODE, __ns:=NAMESPACE, private parameters (_base_watchdog_timeout:=0.5)."
    )] = None,
    robots: Robots = None,
    lockstep: Lockstep = None,
    strict_lockstep: StrictLockstep = False,
    grace: Grace = 1.0,
    startup_grace: StartupGrace = 2.0,
    time: SimulatedTime = None,
    seed: Seed = 0,
    out: Annotated[Path | None, typer.Option(
        help="Run folder [default: runs/SCENARIO-ros-sSEED, or -2, -3... when taken]")] = None,
    timeout: Timeout = 10.0,
    watchdog: Annotated[float, typer.Option(
        help="Realtime: stop a robot whose commands stop for this many simulated seconds "
             "(stage_ros' base_watchdog_timeout; the private parameter "
             "_base_watchdog_timeout:=S sets it too).")] = 0.2,
    map_resolution: MapResolution = 0.05,
    robot_logs: RobotLogs = "auto",
    param: Params = None,
    view: Annotated[str, typer.Option(help="Live view: step, 1s, 10s or off.")] = "off",
    video: Annotated[Path | None, typer.Option(help="Also export a video of the run.")] = None,
    record_scans: RecordScans = False,
    names: Names = "mimics",
    publish_map_odom: PublishMapOdom = None,
) -> None:
    """Run a simulation as a ROS node: robots are driven by commands received from ROS.

    Per robot i, under /robot_i/: odom (nav_msgs/Odometry: the odometer, in
    robot_i/odom, its start pose), pose (the positioning sensor, in map),
    ground_truth, scan (sensor_msgs/LaserScan), goal (geometry_msgs/PoseStamped,
    latched); it listens to cmd (std_msgs/Float64MultiArray [speed_ref,
    heading_ref(, stamp)]) and cmd_vel (geometry_msgs/Twist). Also /map
    (latched nav_msgs/OccupancyGrid), /clock and tf2 frames map -> robot_i/odom
    -> robot_i/base_link -> robot_i/laser, live markers on /mimics/markers, the
    run's parameters under /mimics (and /use_sim_time), and std_srvs/Trigger
    services /mimics/pause, resume, step and reset (a reset starts the run
    again in RUN-reset-1, ...). --names stage: stage_ros' names instead, the
    node /stageros, realtime by default, reset_positions, no map -> odom (as
    stage_ros: --publish-map-odom adds it), robots that stop (goal, collision)
    going on publishing, still, with is_crashed (std_msgs/Int8), and scans with
    range_max for no return and intensities. After SCENARIO,
    ROS arguments as roslaunch passes them (base_scan:=scan, __name:=...).
    SIGINT or SIGTERM ends the run at a step boundary (status interrupted,
    summary written, exit 130 or 143). Needs ROS 1 (Debian's python3-rospy and
    message packages) and a running master (ROS_MASTER_URI). See
    docs/how-to/ros.md.
    """
    from mimics.interfaces.cli.run_summary import (
        check_repeated,
        export_video,
        parse_params,
        print_summary,
    )
    bad = next((arg for arg in ros_args or [] if ":=" not in arg), None)
    if bad is not None:
        raise fail(f"{bad!r}: expected one argument, SCENARIO, then only ROS arguments "
                   "NAME:=VALUE (remaps such as base_scan:=scan, __name:=, __ns:=)")
    lockstep = check_bridge_arguments(
        lockstep=lockstep, strict_lockstep=strict_lockstep, names=names, robots=robots,
        time=time, timeout=timeout, grace=grace, startup_grace=startup_grace,
        watchdog=watchdog, map_resolution=map_resolution, robot_logs=robot_logs)
    from mimics.interfaces.ros.names import check_name_set

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
    from mimics.interfaces.ros.system_ros import require_master, require_ros

    try:
        require_ros()
        require_master()
    except MimicsError as exc:
        raise fail(str(exc)) from None
    from mimics.interfaces.cli.compiling.first_run import compiles_started, kernels_compiled_ahead

    with compiles_started():  # a fresh install's compiles start before Numba is imported
        from mimics.interfaces.live_view import VIEW_CHOICES, make_live_view
        from mimics.interfaces.ros.bridge import BridgeOptions, run_ros
        from mimics.interfaces.ros.stopping import RunInterrupted, StopRequest, exit_status
        from mimics.records.naming import new_run_folder

        if view not in VIEW_CHOICES:
            raise fail(f"--view: expected one of {', '.join(VIEW_CHOICES)}, got {view!r}")
        live = make_live_view(view)
    try:
        # the default name, never one taken (-2, -3...): a run never replaces another;
        # absolute, so that the message says where it is (roslaunch runs us in $ROS_HOME)
        folder = out or new_run_folder("runs", Path(scenario).stem, "ros", seed).absolute()
        options = BridgeOptions(lockstep=lockstep, timeout=timeout,
                                map_resolution=map_resolution, watchdog=watchdog, names=names,
                                grace=None if strict_lockstep else grace,
                                startup_grace=startup_grace, publish_map_odom=publish_map_odom)
        folders: list[Path] = []  # more than one after a reset (/mimics/reset)
        stop = StopRequest()  # SIGINT, SIGTERM: the run ends at a step boundary
        with kernels_compiled_ahead():
            result = run_ros(scenario, folder, options=options, params=params, time=time,
                             seed=seed, robot_logs=robot_logs,  # type: ignore[arg-type]
                             observers=(live,) if live is not None else (),
                             record_scans=record_scans, folders=folders,
                             ros_args=list(ros_args or []), stop=stop)
    except RunInterrupted as exc:
        fail(str(exc))
        raise typer.Exit(exit_status(exc.signum)) from None
    except MimicsError as exc:
        raise fail(str(exc)) from None
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


def ros_files_command(
    out: Annotated[Path, typer.Option(help="Folder to write the package mimics_launch into "
                                           "(created; its parent must exist).")],
    robots: Annotated[int, typer.Option(help="Robots the launch file runs and whose scans "
                                             "the RViz config shows.")] = 4,
    names: Annotated[str, typer.Option(help="Name set the launch file runs and the RViz "
                                            "config shows: mimics or stage (node "
                                            "/stageros).")] = "mimics",
    scenario: Annotated[str, typer.Option(help="Scenario the launch file runs (roslaunch's "
                                               "scenario:= replaces it).")] = "line",
) -> None:
    """Write a roslaunch package (launch file, RViz config) that runs mimics ros with RViz.

    Writes OUT/mimics_launch/: package.xml, launch/mimics.launch (master,
    mimics ros SCENARIO --robots N --names SET, RViz), rviz/mimics.rviz (/map,
    /robot_i/scan, tf, /mimics/markers) and scripts/mimics_ros. Put OUT on
    ROS_PACKAGE_PATH, then `roslaunch mimics_launch mimics.launch` (scenario:=,
    args:= replace what it was written for).
    Replaces no file. See docs/how-to/ros.md.
    """
    from mimics.interfaces.ros.launch_files import write_ros_files

    try:
        written = write_ros_files(out, robots, names, scenario)
    except MimicsError as exc:
        raise fail(str(exc)) from None
    for path in written:
        print(f"wrote {path}")
    print(f"then: export ROS_PACKAGE_PATH={out.resolve()}:$ROS_PACKAGE_PATH")
