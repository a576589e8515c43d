"""`mimics ros`: a simulation run as a ROS 1 node, driven by ROS controllers.

The main CLI registers it with ``app.command("ros")(ros_command)``. Bad
input, no ROS installed or no master reachable: one line on stderr, status
2. A run that a lockstep time-out ended: its summary, then one line on
stderr, status 1.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import typer

import mimics.interfaces.cli.ros_common as common
from mimics.interfaces.cli.output import fail
from mimics.world.errors import MimicsError


def ros_command(
    scenario: Annotated[str, typer.Argument(help="Built-in scenario name or a .py/.toml file.")],
    ros_args: Annotated[list[str] | None, typer.Argument(
        metavar="[FROM:=TO]...",
        help="ROS arguments, as roslaunch passes them: remaps (base_scan:=scan), "
             "__name:=NODE, __ns:=NAMESPACE, private parameters (_base_watchdog_timeout:=0.5)."
    )] = None,
    robots: common.Robots = None,
    lockstep: common.Lockstep = None,
    strict_lockstep: common.StrictLockstep = False,
    grace: common.Grace = 1.0,
    startup_grace: common.StartupGrace = 2.0,
    time: common.SimulatedTime = None,
    seed: common.Seed = 0,
    out: Annotated[Path | None, typer.Option(
        help="Run folder [default: runs/SCENARIO-ros-sSEED, or -2, -3... when taken]")] = None,
    timeout: common.Timeout = 10.0,
    watchdog: common.Watchdog = 0.2,
    map_resolution: common.MapResolution = 0.05,
    robot_logs: common.RobotLogs = "auto",
    param: common.Params = None,
    view: common.View = "off",
    video: common.Video = None,
    record_scans: common.RecordScans = False,
    names: common.Names = "mimics",
    publish_map_odom: common.PublishMapOdom = None,
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
    bad = next((arg for arg in ros_args or [] if ":=" not in arg), None)
    if bad is not None:
        raise fail(f"{bad!r}: expected one argument, SCENARIO, then only ROS arguments "
                   "NAME:=VALUE (remaps such as base_scan:=scan, __name:=, __ns:=)")
    options = common.check_bridge_arguments(
        lockstep=lockstep, strict_lockstep=strict_lockstep, names=names, robots=robots,
        time=time, timeout=timeout, grace=grace, startup_grace=startup_grace,
        watchdog=watchdog, map_resolution=map_resolution, robot_logs=robot_logs,
        publish_map_odom=publish_map_odom)
    params = common.run_inputs(scenario, names=names, param=param, robots=robots, time=time,
                               out=out, view=view)
    from mimics.interfaces.ros.system_ros import require_master, require_ros

    try:
        require_ros()
        require_master()
    except MimicsError as exc:
        raise fail(str(exc)) from None

    def load_runner() -> Callable[..., Any]:
        from mimics.interfaces.ros.bridge import run_ros

        return run_ros

    common.run_bridge(scenario, "ros", load_runner, options, out=out, seed=seed, view=view,
                      video=video, params=params, time=time, robot_logs=robot_logs,
                      record_scans=record_scans, ros_args=list(ros_args or []))


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
