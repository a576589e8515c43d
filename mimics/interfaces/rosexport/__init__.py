"""Finished runs as files that ROS tools read: MCAP (ROS 2 messages) and ROS 1 bags.

``mimics export RUN --mcap run.mcap`` (Foxglove opens it as it is) and
``--bag run.bag`` (rosbag, RViz through ``rosbag play``, PlotJuggler). The
topics and frames are the live bridge's (``mimics ros``), under its
``mimics`` or ``stage`` name set (``--names``), listed in
:mod:`mimics.interfaces.rosexport.topics`; the odometer, which a run folder
does not record, is rebuilt from the trajectory and the seed
(:mod:`~.odometer`). One module builds each family of messages (``grid``,
``transforms``, ``odometry``, ``laser``, ``markers``), :mod:`~.conversion` builds and
serialises every message, :mod:`~.writer` writes the files. The run is read
through :func:`mimics.records.run_folder.load_run`. Needs the ``export``
extra (``pip install 'mimics-sim[export]'``: the ``rosbags`` package).

>>> import tempfile, mimics
>>> from pathlib import Path
>>> folder = Path(tempfile.mkdtemp())
>>> _ = mimics.simulate("line", "go_to_goal", robots=2, time=1, seed=1, out=folder / "run",
...                     record_scans=True)
>>> counts = export_run(folder / "run", mcap=folder / "run.mcap")
>>> counts[0].messages["/robot_1/scan"], counts[0].messages["/robot_1/odom"]
(11, 11)
>>> counts = export_run(folder / "run", mcap=folder / "stage.mcap", names="stage")
>>> counts[0].messages["/robot_1/base_scan"], counts[0].messages["/robot_1/odom"]
(11, 11)
"""

from __future__ import annotations

from pathlib import Path

from mimics.world.errors import MimicsError

__all__ = ["export_run"]


def export_run(folder: str | Path, *, mcap: str | Path | None = None,
               bag: str | Path | None = None, resolution: float | None = None,
               scans: bool | None = None, names: str = "mimics") -> list:
    """Export a recorded run as MCAP and/or a ROS 1 bag.

    Args:
        folder: the run folder (a finished run, or what a killed one kept).
        mcap: the MCAP file to write (replaced if it exists; never a file of the run
            folder, nor the same file as ``bag``).
        bag: the ROS 1 bag to write (replaced if it exists, with the same exceptions).
        resolution: the occupancy grid's cell size in metres (default 0.05).
        scans: ``None``: the laser scans when the run recorded them; ``True``:
            they are required; ``False``: left out.
        names: the live bridge's name set whose topics and frames to write:
            ``"mimics"`` or ``"stage"`` (``stage_ros``' names).

    Returns:
        One :class:`~mimics.interfaces.rosexport.writer.ExportCounts` per file written.

    Raises:
        MimicsError: in one line, when ``folder`` is not a run, scans are
            required but were not recorded, no output is given, the
            resolution is not positive, ``names`` is no name set, an output cannot be written
            (its folder must exist: none is created), lies inside the run folder
            or is the other output's file.
    """
    from mimics.interfaces.ros.names import check_name_set
    from mimics.interfaces.rosexport.writer import (
        DEFAULT_RESOLUTION,
        ExportSource,
        check_target,
        write_bag,
        write_mcap,
    )
    from mimics.records.run_folder import load_run
    from mimics.world.occupancy import check_resolution
    from mimics.world.output_paths import check_outputs

    if mcap is None and bag is None:
        raise MimicsError("export: nothing to write (give --mcap FILE and/or --bag FILE)")
    check_name_set(names, "--names")
    resolution = DEFAULT_RESOLUTION if resolution is None else resolution
    check_resolution(resolution)
    run = load_run(folder)  # only reads: a folder that is no run is named as such first
    # before writing: an output in the run folder, or both outputs one file, would lose the
    # run or one export
    check_outputs({"--mcap": mcap, "--bag": bag}, {"the run folder": folder})
    for target in (mcap, bag):  # before reading the rows: nothing is done for a bad path
        if target is not None:
            check_target(Path(target))
    if scans and not run.has_scans:
        raise MimicsError(f"{run.path}: --scans asked for, but this run recorded no laser scans "
                          f"(run it again with --record-scans)")
    with_scans = run.has_scans if scans is None else scans
    if with_scans:
        _ = run.scans  # an unreadable scans file fails here, before any output
    source = ExportSource.of(run, names)
    written = []
    for target, write in ((mcap, write_mcap), (bag, write_bag)):
        if target is None:
            continue
        try:
            written.append(write(source, Path(target), resolution, with_scans))
        except OSError as exc:
            raise MimicsError(f"{target}: cannot write here ({exc.strerror or exc})") from None
    return written
