"""`mimics ros2`: a simulation run on the ROS 2 DDS graph (Cyclone DDS), driven by ROS 2 nodes.

The main CLI registers it with ``app.command("ros2")(ros2_command)``. Bad
input or no ``cyclonedds``: one line on stderr, status 2. A run that a
lockstep time-out ended: its summary, then one line on stderr, status 1.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

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
    options = common.check_bridge_arguments(
        lockstep=lockstep, strict_lockstep=strict_lockstep, names=names, robots=robots,
        time=time, timeout=timeout, grace=grace, startup_grace=startup_grace,
        watchdog=watchdog, map_resolution=map_resolution, robot_logs=robot_logs,
        publish_map_odom=publish_map_odom)
    params = common.run_inputs(scenario, names=names, param=param, robots=robots, time=time,
                               out=out, view=view)
    from mimics.interfaces.ros2 import require_cyclonedds

    try:
        require_cyclonedds()
        from mimics.interfaces.ros2.transport import domain_id

        domain = domain_id()
    except MimicsError as exc:
        raise fail(str(exc)) from None

    def load_runner() -> Callable[..., Any]:
        from mimics.interfaces.ros2.bridge import run_ros2

        return run_ros2

    common.run_bridge(scenario, "ros2", load_runner, options, out=out, seed=seed, view=view,
                      video=video, params=params, time=time, robot_logs=robot_logs,
                      record_scans=record_scans, domain=domain)
