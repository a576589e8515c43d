"""Writing a finished run as an MCAP file (ROS 2 messages) or a ROS 1 bag.

Both are written by the ``rosbags`` package: the MCAP through its rosbag2
writer with MCAP storage (zstd-compressed chunks, ``ros2msg`` schemas, CDR
messages: what Foxglove opens as it is), taken out of the rosbag2 folder as a
single file; the bag through its ROS 1 writer. Each is written under a
temporary name beside the target and renamed when complete, so a failed
export leaves no half file. Every message's log time equals its header stamp:
the simulated time from a fixed epoch, 2000-01-01T00:00:00Z
(:data:`~mimics.interfaces.rosexport.pieces.EXPORT_EPOCH_NS`).
"""

from __future__ import annotations

import heapq
import os
import shutil
import tempfile
from collections import Counter
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from rosbags.rosbag1 import Writer as Ros1Writer
from rosbags.rosbag2 import Writer as Ros2Writer
from rosbags.rosbag2.enums import CompressionFormat, CompressionMode, StoragePlugin

from mimics.engine.state import TypeArrays
from mimics.interfaces.ros.names import RosNames
from mimics.interfaces.rosexport.conversion import Messages, Stamped
from mimics.interfaces.rosexport.grid import map_messages
from mimics.interfaces.rosexport.laser import scan_messages
from mimics.interfaces.rosexport.markers import marker_messages
from mimics.interfaces.rosexport.odometer import (
    OdometerTrack,
    measured_velocity,
    odometer_gap,
    odometer_track,
)
from mimics.interfaces.rosexport.odometry import odometry_messages
from mimics.interfaces.rosexport.source import Trajectory
from mimics.interfaces.rosexport.topics import LATCHED, MAP_FRAME
from mimics.interfaces.rosexport.transforms import tf_messages, tf_static_messages
from mimics.records.run_folder import Run
from mimics.world.errors import MimicsError

DEFAULT_RESOLUTION = 0.05  # m per occupancy grid cell


@dataclass
class ExportCounts:
    """What an export wrote: messages per topic, the file, and what was left out and why."""

    path: Path
    messages: Counter[str] = field(default_factory=Counter)
    notes: list[str] = field(default_factory=list)

    @property
    def total(self) -> int:
        """All messages written."""
        return sum(self.messages.values())


@dataclass(frozen=True)
class ExportSource:
    """What both files of an export are written from: the run, its rows, the names to
    use and the readings rebuilt from the seed (None: they cannot be, see ``notes``)."""

    run: Run
    trajectory: Trajectory
    names: RosNames
    types: TypeArrays
    odometer: OdometerTrack | None
    velocity: np.ndarray | None
    notes: tuple[str, ...]

    @classmethod
    def of(cls, run: Run, name_set: str) -> ExportSource:
        """The source of ``run`` under name set ``name_set`` (``mimics`` or ``stage``)."""
        scenario, seed = run.scenario, run.info.get("seed")
        trajectory = Trajectory.of(run)
        names = RosNames(name_set, scenario.robot_count)
        velocity = measured_velocity(trajectory, scenario, seed)
        gap = odometer_gap(trajectory, scenario, seed)
        odometer = None if gap is not None else odometer_track(trajectory, scenario, int(seed))
        notes = []
        if gap is not None or velocity is None:
            why = gap or "the run's seed is not recorded in scenario.toml"
            notes.append(f"no odom topics nor odom frames: the odometer cannot be rebuilt "
                         f"({why}); /tf places each robot's body straight in {MAP_FRAME}")
        return cls(run, trajectory, names, TypeArrays.from_scenario(scenario),
                   odometer if velocity is not None else None, velocity, tuple(notes))


def run_messages(messages: Messages, source: ExportSource, resolution: float,
                 scans: bool) -> Iterator[Stamped]:
    """Every message of the export, merged in log-time order (stable within a time)."""
    run, trajectory, names = source.run, source.trajectory, source.names
    scenario = run.scenario
    families: list[Iterable[Stamped]] = [
        map_messages(messages, scenario.map, resolution),
        tf_static_messages(messages, names, source.types.beam_count),
        marker_messages(messages, trajectory, scenario, names),
        tf_messages(messages, trajectory, names, source.odometer),
        odometry_messages(messages, trajectory, names, source.types, source.odometer,
                          source.velocity),
    ]
    if scans:
        families.append(scan_messages(messages, run.scans, scenario.settings.dt, names))
    return heapq.merge(*families, key=lambda stamped: stamped.time)


def write_mcap(source: ExportSource, target: Path, resolution: float,
               scans: bool) -> ExportCounts:
    """Write the run as one MCAP file of ROS 2 messages at ``target``."""
    messages = Messages(2)
    counts = ExportCounts(target, notes=list(source.notes))
    with _temporary_folder(target) as folder:
        bag = folder / "bag"
        writer = Ros2Writer(bag, version=Ros2Writer.VERSION_LATEST,
                            storage_plugin=StoragePlugin.MCAP)
        writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
        with writer:
            _write_messages(writer, run_messages(messages, source, resolution, scans),
                            messages, counts, latching=False)
        os.replace(bag / "bag.mcap", target)
    return counts


def write_bag(source: ExportSource, target: Path, resolution: float,
              scans: bool) -> ExportCounts:
    """Write the run as a ROS 1 bag at ``target``."""
    messages = Messages(1)
    counts = ExportCounts(target, notes=list(source.notes))
    with _temporary_folder(target) as folder:
        path = folder / "run.bag"
        with Ros1Writer(path) as writer:
            _write_messages(writer, run_messages(messages, source, resolution, scans),
                            messages, counts, latching=True)
        os.replace(path, target)
    return counts


def _write_messages(writer: Any, stream: Iterable[Stamped], messages: Messages,
                    counts: ExportCounts, *, latching: bool) -> None:
    """Write ``stream`` through a rosbags writer, one connection per topic (ROS 1 bags
    mark the latched topics)."""
    connections: dict[str, Any] = {}
    for stamped in stream:
        connection = connections.get(stamped.topic)
        if connection is None:
            extra = ({"latching": 1 if stamped.topic in LATCHED else None} if latching else {})
            connection = writer.add_connection(stamped.topic, stamped.message.__msgtype__,
                                               typestore=messages.store, **extra)
            connections[stamped.topic] = connection
        writer.write(connection, stamped.time, messages.serialize(stamped.message))
        counts.messages[stamped.topic] += 1


def check_target(target: Path) -> None:
    """Refuse an output that is a folder, or whose folder does not exist (none is created:
    a typing mistake in the path should not leave new folders behind).

    Raises:
        MimicsError: in one line naming the path.
    """
    if target.is_dir():
        raise MimicsError(f"{target}: is a directory (expected a file name to write)")
    folder = target.parent
    if not folder.is_dir():
        what = "is not a folder" if folder.exists() else "does not exist"
        raise MimicsError(f"{target}: the folder {str(folder)!r} {what} (create it first)")


@contextmanager
def _temporary_folder(target: Path) -> Iterator[Path]:
    """A fresh folder beside ``target`` (same file system: the rename is atomic), removed
    on exit; a one-line error when ``target`` cannot be written there."""
    check_target(target)
    try:
        folder = Path(tempfile.mkdtemp(prefix=f".{target.name}.", dir=target.parent))
    except OSError as exc:
        raise MimicsError(f"{target}: cannot write here ({exc.strerror or exc})") from None
    try:
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)
