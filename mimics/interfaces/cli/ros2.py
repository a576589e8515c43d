"""`mimics ros2`: a simulation run on the ROS 2 DDS graph (Cyclone DDS), driven by ROS 2 nodes.

The main CLI registers it with ``app.command("ros2")(ros2_command)``. Bad
input or no ``cyclonedds``: one line on stderr, status 2. A run that a
lockstep time-out ended: its summary, then one line on stderr, status 1.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

import mimics.interfaces.cli.ros_common as common
from mimics.interfaces.cli.output import fail
from mimics.world.errors import MimicsError


def ros2_command(
    scenario: Annotated[str, typer.Argument(help="Built-in scenario name or a .py/.toml file.")],
    robots: common.Robots = None,
    lockstep: common.Lockstep = None,
    strict_lockstep: common.StrictLockstep = False,
    grace: common.Grace = 1.0,
    startup_grace: common.StartupGrace = 2.0,
    time: common.SimulatedTime = None,
    seed: common.Seed = 0,
    out: Annotated[Path | None, typer.Option(
        help="Run folder [default: runs/SCENARIO-ros2-sSEED, or -2, -3... when taken]")]
    = None,
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
    """Run a simulation on the ROS 2 graph: robots are driven by Twists from ROS 2 nodes.

    Per robot i, under /robot_i/: odom (nav_msgs/Odometry: the odometer, in
    robot_i/odom, its start pose), pose (the positioning sensor, in map),
    ground_truth, scan (sensor_msgs/LaserScan), goal (geometry_msgs/PoseStamped,
    transient local); it listens to cmd_vel (geometry_msgs/Twist). Also /map
    (transient local nav_msgs/OccupancyGrid), /clock, /tf, /tf_static and
    /mimics/markers, and std_srvs/Trigger services /mimics/pause, resume, step
    and reset (framed as rmw_cyclonedds_cpp frames them). --names stage:
    stage_ros' names and what its nodes see (no map -> odom unless
    --publish-map-odom, stopped robots publishing with is_crashed, scan
    intensities), as for mimics ros. DDS domain
    ROS_DOMAIN_ID; Cyclone DDS's settings from CYCLONEDDS_URI. Nodes run with
    use_sim_time:=true. SIGINT or SIGTERM ends the run at a step boundary
    (status interrupted, summary written). Needs the ros2 extra (cyclonedds).
    See docs/how-to/ros2.md.
    """
    lockstep = common.check_bridge_arguments(
        lockstep=lockstep, strict_lockstep=strict_lockstep, names=names, robots=robots,
        time=time, timeout=timeout, grace=grace, startup_grace=startup_grace,
        watchdog=watchdog, map_resolution=map_resolution, robot_logs=robot_logs)
    params = common.run_inputs(scenario, names=names, param=param, robots=robots, time=time,
                        out=out, view=view)
    from mimics.interfaces.ros2 import require_cyclonedds

    try:
        require_cyclonedds()
        from mimics.interfaces.ros2.transport import domain_id

        domain = domain_id()
    except MimicsError as exc:
        raise fail(str(exc)) from None
    from mimics.interfaces.cli.compiling.first_run import (
        compiles_started,
        kernels_compiled_ahead,
    )

    with compiles_started():  # a fresh install's compiles start before Numba is imported
        from mimics.interfaces.live_view import make_live_view
        from mimics.interfaces.ros.stopping import RunInterrupted, StopRequest, exit_status
        from mimics.interfaces.ros2.bridge import run_ros2
        from mimics.records.naming import new_run_folder

        live = make_live_view(view)

    stop = StopRequest()  # SIGINT, SIGTERM: the run ends at a step boundary
    try:
        folder = out or new_run_folder("runs", Path(scenario).stem, "ros2", seed).absolute()
        options = common.bridge_options(
            lockstep=lockstep, strict_lockstep=strict_lockstep, timeout=timeout,
            map_resolution=map_resolution, watchdog=watchdog, names=names, grace=grace,
            startup_grace=startup_grace, publish_map_odom=publish_map_odom)
        folders: list[Path] = []  # more than one after a reset (/mimics/reset)
        with kernels_compiled_ahead():
            result = run_ros2(scenario, folder, options=options, params=params, time=time,
                              seed=seed, robot_logs=robot_logs,  # type: ignore[arg-type]
                              observers=(live,) if live is not None else (),
                              record_scans=record_scans, folders=folders, stop=stop,
                              domain=domain)
    except RunInterrupted as exc:
        fail(str(exc))
        raise typer.Exit(exit_status(exc.signum)) from None
    except MimicsError as exc:
        raise fail(str(exc)) from None
    common.report_end(result, folder, folders, video, stop)
