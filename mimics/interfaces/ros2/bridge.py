"""A simulation run on the ROS 2 DDS graph: the ROS 2 transport of the shared bridge core.

:func:`run_ros2` builds the run through the ordinary runner
(``mimics.records.runner.prepare`` and ``run_to_folder``), with
:class:`Ros2Bridge` as the observer that publishes each step and
:class:`~mimics.interfaces.ros.references.RosReferences` as the algorithm
returning the commands received: the run folder, logs, summary and end
criteria are those of ``mimics run``. Lockstep, realtime pace, the wait for
the nodes and stopping on SIGINT/SIGTERM are the ROS 1 bridge's
(:class:`~mimics.interfaces.ros.bridge_core.BridgeCore`).

Per step ``k``: ``/clock``, every active robot's ``odom``, ``pose``
(``mimics`` names), ground truth and scan, ``/tf`` and ``/mimics/markers``,
stamped ``t_k`` (under the ``stage`` names also those of the robots that
stopped, and each robot's ``is_crashed``; what they carry is the shared
core's, :mod:`~mimics.interfaces.ros.readings`); once, transient local:
``/map``, the goals and ``/tf_static``.
Lockstep waits for one command per active robot before stepping: a
``geometry_msgs/Twist`` on its ``cmd_vel`` or (``mimics`` names) a
``std_msgs/Float64MultiArray`` ``[speed_ref, heading_ref(, stamp)]`` on its
``cmd``. Before step 0 the run waits until every robot's commands have a
matched writer and one of its per-step topics a matched
reader (then, up to ``startup_grace``, for readers of all of them).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.interfaces.ros.bridge_core import (
    BridgeCore,
    BridgeOptions,
    load_run_scenario,
    options_record,
    run_with_resets,
)
from mimics.interfaces.ros.names import MAP_FRAME, RosNames
from mimics.interfaces.ros.occupancy import rasterise
from mimics.interfaces.ros.planar import BadCommand
from mimics.interfaces.ros.readings import (
    OdometryReadings,
    ScanReadings,
    fixed_frames,
    stalled,
    step_markers,
)
from mimics.interfaces.ros.stopping import StopRequest
from mimics.interfaces.ros2 import conversion as convert
from mimics.interfaces.ros2 import messages as msg
from mimics.interfaces.ros2 import qos
from mimics.interfaces.ros2.transport import DdsGraph, domain_id, matched_readers, matched_writers

if TYPE_CHECKING:
    from cyclonedds.pub import DataWriter

    from mimics.engine.outcome import RunResult
    from mimics.engine.simulation import Simulation
    from mimics.interfaces.ros.inbox import Inbox
    from mimics.records.recorder import RobotLogs

MARKERS_TOPIC = "/mimics/markers"


class Ros2Bridge(BridgeCore):
    """The observer that publishes a run's steps on the DDS graph of ``graph``."""

    def __init__(self, sim: Simulation, inbox: Inbox, options: BridgeOptions, graph: DdsGraph,
                 stop: StopRequest | None = None) -> None:
        super().__init__(inbox, options, sim.scenario.settings.dt, stop)
        n, beams = sim.state.n, sim.types.beam_count
        self.graph = graph
        self.names = names = RosNames(options.names, n)
        self.readings = OdometryReadings(sim)
        self.scan_readings = ScanReadings(sim)
        self._markers = convert.IdlMessages()
        writer = graph.writer
        self.clock = writer("/clock", msg.Clock, qos.CLOCK)
        self.odom = [writer(names.odom(i), msg.Odometry, qos.STREAM) for i in range(n)]
        self.pose = [writer(topic, msg.Odometry, qos.STREAM)
                     for i in range(n) if (topic := names.pose(i)) is not None]
        self.truth = [writer(names.ground_truth(i), msg.Odometry, qos.STREAM)
                      for i in range(n)]
        self.scans = {i: writer(names.scan(i), msg.LaserScan, qos.STREAM)
                      for i in np.flatnonzero(beams > 0).tolist()}
        self.stalls = {i: writer(topic, msg.Int8, qos.STREAM)
                       for i in range(n) if (topic := names.stall(i)) is not None}
        self.tf = writer("/tf", msg.TFMessage, qos.STREAM)
        self.markers = writer(MARKERS_TOPIC, msg.MarkerArray, qos.STREAM)
        # once, transient local: a node that starts later still gets them
        map_writer = writer("/map", msg.OccupancyGrid, qos.LATCHED)
        map_writer.write(convert.grid(rasterise(sim.scenario.map, options.map_resolution), 0.0))
        static = writer("/tf_static", msg.TFMessage, qos.TF_STATIC)
        static.write(msg.TFMessage([convert.transform(0.0, parent, child, 0.0, 0.0, 0.0)
                                    for parent, child in fixed_frames(beams, names)]))
        for i, target in enumerate(sim.state.goal):
            if np.all(np.isfinite(target)):
                writer(names.goal(i), msg.PoseStamped, qos.LATCHED).write(
                    convert.goal(0.0, target))
        dt = sim.scenario.settings.dt
        self.cmd_vel = [graph.reader(names.cmd_vel(i), msg.Twist, qos.COMMANDS,
                                     self._on_command(i, convert.command_from_twist))
                        for i in range(n)]
        self.cmd = [graph.reader(topic, msg.Float64MultiArray, qos.COMMANDS,
                                 self._on_command(i, convert.command_from_array, dt))
                    if (topic := names.cmd(i)) is not None else None for i in range(n)]

    def _on_command(self, robot: int, convert_message: Any, *args: Any) -> Any:
        def deliver(message: Any) -> None:  # on Cyclone's receiving thread
            try:
                self.inbox.deliver(robot, convert_message(message, *args))
            except BadCommand as exc:
                self.inbox.reject(robot, str(exc))
        return deliver

    def _per_step(self, robot: int) -> list[DataWriter]:
        scan = self.scans.get(robot)
        return [self.odom[robot], self.truth[robot], *self.pose[robot:robot + 1],
                *([scan] if scan is not None else [])]

    def _observed(self, robot: int) -> bool:
        return any(matched_readers(writer) > 0 for writer in self._per_step(robot))

    def _fully_observed(self, robot: int) -> bool:
        return all(matched_readers(writer) > 0 for writer in self._per_step(robot))

    def _commands_connected(self, robot: int) -> int:
        cmd = self.cmd[robot]
        return matched_writers(self.cmd_vel[robot]) + (
            matched_writers(cmd) if cmd is not None else 0)

    def commands_connected(self, robot: int) -> int:
        """How many writers of the robot's ``cmd_vel`` and ``cmd`` are matched (the
        watchdog's "its node has gone")."""
        return self._commands_connected(robot)

    def _starting(self) -> None:
        """Nothing to set: a ROS 2 node's ``use_sim_time`` is its own parameter."""

    def _send(self, sim: Simulation, ids: np.ndarray) -> None:
        state, names, readings = sim.state, self.names, self.readings
        seconds = state.time
        self.clock.write(convert.clock(seconds))
        readings.update(sim)
        transforms = []
        flags = stalled(state) if self.stalls else None
        map_odom = self.options.map_odom
        for i in ids.tolist():
            body = names.body_frame(i)
            self.odom[i].write(convert.odometry(seconds, names.odom_frame(i), body,
                                                readings.odom(sim, i)))
            if self.pose:
                self.pose[i].write(convert.odometry(seconds, MAP_FRAME, body,
                                                    readings.pose(sim, i)))
            self.truth[i].write(convert.odometry(seconds, MAP_FRAME, body,
                                                 readings.truth(sim, i)))
            transforms += convert.odometry_transforms(seconds, names.odom_frame(i), body,
                                                      state.measured_pose[i],
                                                      readings.frames.pose[i], map_odom)
            if flags is not None:
                self.stalls[i].write(msg.Int8(int(flags[i])))
            self._send_scan(sim, i)
        if transforms:
            self.tf.write(msg.TFMessage(transforms))
        if matched_readers(self.markers) > 0:  # built only when someone listens
            self.markers.write(msg.MarkerArray(step_markers(self._markers, sim)))

    def _send_scan(self, sim: Simulation, robot: int) -> None:
        writer = self.scans.get(robot)
        if writer is None:
            return
        types, stage = sim.types, self.names.stage
        ranges, hit = self.scan_readings.scan(sim, robot)
        # stage_ros: range_max where a beam hit nothing (not inf), and intensities
        writer.write(convert.scan(
            self.names.laser_frame(robot), sim.state.time, ranges, hit,
            types.beam_offsets[robot, :len(ranges)], float(types.max_range[robot]),
            sim.scenario.settings.dt, no_return_at_max=stage, intensities=stage))

    def close(self) -> None:
        """Withdraw every topic and leave the domain."""
        self.graph.close()


def run_ros2(scenario: str | Path, folder: str | Path, *, options: BridgeOptions,
             params: dict[str, Any] | None = None, time: float | None = None, seed: int = 0,
             robot_logs: RobotLogs = "auto", observers: tuple[Any, ...] = (),
             record_scans: bool = False, folders: list[Path] | None = None,
             stop: StopRequest | None = None, domain: int | None = None) -> RunResult:
    """Run ``scenario`` on the ROS 2 graph, driven by ROS 2 controllers; record it into ``folder``.

    Args:
        scenario: a built-in scenario name or a scenario file.
        folder: the run folder.
        options: lockstep or realtime, the time-out, names, the map's resolution.
        params: scenario parameters (``{"robots": 5}``).
        time: simulated seconds (default: the scenario's).
        seed: the run's seed.
        robot_logs: per-robot text logs, as for ``mimics run``.
        observers: more observers of the run (a live view, say).
        record_scans: also record the laser scans, as ``mimics run --record-scans``.
        folders: a list that receives each run's folder in order: ``folder``,
            then one per reset (``/mimics/reset``).
        stop: where SIGINT and SIGTERM are recorded (None: handled here, from the
            main thread); the run then ends at the next step boundary.
        domain: the DDS domain (None: ``ROS_DOMAIN_ID``).

    Returns:
        The outcome of the last run (the one after the last reset, if any).

    Raises:
        MimicsError: when ``ROS_DOMAIN_ID`` or a scenario argument is bad or, in
            lockstep, no controller connects in time.
    """
    import numba

    from mimics.interfaces.ros.inbox import Inbox
    from mimics.interfaces.ros.references import RosReferences
    from mimics.interfaces.ros.run_control import RunControl
    from mimics.interfaces.ros2.services import DdsServices
    from mimics.records.runner import prepare

    domain = domain_id() if domain is None else domain
    numba.set_num_threads(1)  # the DDS round trip dominates a step (see ros.bridge)
    built = load_run_scenario(scenario, options, params, seed)  # stage names: robots stall
    stop = stop or StopRequest()
    inbox = Inbox(built.robot_count, options.lockstep, options.timeout, stop, options.grace)

    def simulation(bridge: Ros2Bridge | None = None) -> tuple[Simulation, RosReferences]:
        """The run from its start state, and the algorithm returning the commands."""
        references = RosReferences(inbox, built.stages[:, 2], options.timeout,
                                   options.timeout_option, options.watchdog)
        if bridge is not None:
            references.publishers, references.names = bridge.commands_connected, bridge.names
        made = prepare(built, references.controller("ros2"), time=time, seed=seed,
                       observers=observers)
        return made, references

    sim, references = simulation()
    with stop.handling_signals():
        bridge = Ros2Bridge(sim, inbox, options, DdsGraph(domain), stop)
        references.publishers, references.names = bridge.commands_connected, bridge.names
        control = RunControl(options.timeout + 5.0)
        services = DdsServices(bridge.graph, control, reset_positions=options.names == "stage")
        try:
            return run_with_resets(bridge, control, sim, folder, lambda: simulation(bridge)[0],
                                   folders, stop, robot_logs=robot_logs,
                                   record_scans=record_scans,
                                   extra={"ros2": {**options_record(options), "domain": domain}})
        finally:
            control.run_ended()
            services.close()
            bridge.close()
