"""``mimics export RUN --mcap run.mcap --bag run.bag``: a run as files ROS tools read.

Registered by the main CLI as ``app.command("export")(export_command)``. Every
error a user can cause (not a run folder, scans asked for but not recorded,
an output that cannot be written, the ``export`` extra not installed) is one
line ``mimics: error: ...`` on stderr and exit status 2.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer

from mimics.interfaces.cli.output import fail, say
from mimics.world.errors import MimicsError


def export_command(
    run: Annotated[Path, typer.Argument(help="A run folder (written by `mimics run`).")],
    mcap: Annotated[Path | None, typer.Option(help="Write an MCAP file of ROS 2 messages "
                                              "(Foxglove opens it).")] = None,
    bag: Annotated[Path | None, typer.Option(help="Write a ROS 1 bag.")] = None,
    scans: Annotated[bool | None, typer.Option(
        "--scans/--no-scans", help="Require the laser scans (recorded with --record-scans) / "
        "leave them out [default: included when recorded]", show_default=False)] = None,
    resolution: Annotated[float, typer.Option(help="Occupancy grid cell size (m).")] = 0.05,
    names: Annotated[str, typer.Option(
        help="The live bridge's topic and frame names to write: mimics (/robot_i/odom, "
        "/robot_i/scan...) or stage (stage_ros': odom, base_scan, base_pose_ground_truth, "
        "no robot_i/ prefix for one robot).")] = "mimics",
) -> None:
    """Export a finished run for ROS tools: MCAP (ROS 2 messages) and/or a ROS 1 bag.

    The topics and frames of `mimics ros --names NAMES`: /map
    (nav_msgs/OccupancyGrid), /tf (map -> odom -> body) and /tf_static
    (tf2_msgs/TFMessage), the odometer, positioning (mimics names) and ground
    truth (nav_msgs/Odometry), the scans (sensor_msgs/LaserScan, when the run
    recorded them) and /markers (visualization_msgs/MarkerArray: footprints
    and goals). Stamps are the
    simulated time from 2000-01-01T00:00:00Z (ROS reads a time of 0 as
    unset). Needs the export extra: pip install 'mimics-sim[export]'.
    """
    try:
        from mimics.interfaces.rosexport import export_run
    except ImportError as exc:
        raise fail(f"mimics export needs the export extra ({exc.name} is missing): "
                   f"pip install 'mimics-sim[export]'") from None
    try:
        written = export_run(run, mcap=mcap, bag=bag, resolution=resolution, scans=scans,
                             names=names)
    except MimicsError as exc:
        raise fail(str(exc)) from None
    for note in dict.fromkeys(note for counts in written for note in counts.notes):
        say(f"note: {note}")
    for counts in written:
        topics = len(counts.messages)
        say(f"wrote {counts.path}: {counts.total} messages on {topics} topics")
