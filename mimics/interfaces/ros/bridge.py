"""A simulation run as a ROS node: the capabilities tied to one run.

:func:`run_ros` builds the run through the ordinary runner
(``mimics.records.runner.prepare`` and ``run_to_folder``), with
:class:`RosBridge` as an observer that publishes what each step sensed, and
:class:`~mimics.interfaces.ros.references.RosReferences` as the algorithm
that returns the references received. The run folder, logs, summary and end
criteria are those of ``mimics run``.

Per step ``k`` (time ``t_k``), lockstep: the inbox is told to expect step
``k``'s commands, then ``/clock``, every active robot's ``odom``, ``pose``,
ground truth and ``scan``, and ``/tf`` are published stamped ``t_k`` (under
the stage names also those of the robots that stopped, and ``is_crashed``); the
next step waits for every active robot's command, all within one deadline
(``timeout`` seconds from the step's publication). Realtime: the same
publications, then a sleep until wall time ``start + t_k + dt``; the next
step uses the latest commands, and a robot whose commands stop for
``watchdog`` seconds is stopped.

Topic and frame names come from one
:class:`~mimics.interfaces.ros.names.RosNames` (``--names mimics`` or
``stage``). The per-step topics are latched: a node that subscribes late (to
the scan 0.3 s after the odometry, say) still receives the current step's
message on connecting, and in lockstep the run waits for its command, so no step's
scan is lost, whatever the timing.
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
from mimics.interfaces.ros.names import RosNames
from mimics.interfaces.ros.node import NODE_NAME, STAGE_NODE_NAME, join_ros, private_parameters
from mimics.interfaces.ros.stopping import StopRequest
from mimics.interfaces.ros.system_ros import require_master, require_ros

if TYPE_CHECKING:
    from mimics.engine.outcome import RunResult
    from mimics.engine.simulation import Simulation
    from mimics.interfaces.ros.inbox import Inbox
    from mimics.records.recorder import RobotLogs

__all__ = ["BridgeOptions", "RosBridge", "run_ros"]  # BridgeOptions: where callers import it


class RosBridge(BridgeCore):
    """The observer that publishes a run's steps over ROS 1; created once ``rospy`` is
    initialised. Lockstep, pace and the wait for the nodes are the shared
    :class:`~mimics.interfaces.ros.bridge_core.BridgeCore`'s."""

    def __init__(self, sim: Simulation, inbox: Inbox, options: BridgeOptions,
                 stop: StopRequest | None = None) -> None:
        from mimics.interfaces.ros.clock import ClockPublisher
        from mimics.interfaces.ros.commands import CommandSubscriber
        from mimics.interfaces.ros.frames import FramePublisher
        from mimics.interfaces.ros.goals import GoalPublisher
        from mimics.interfaces.ros.grid_map import MapPublisher
        from mimics.interfaces.ros.markers import MarkerPublisher
        from mimics.interfaces.ros.odometry import OdometryPublisher, StallPublisher
        from mimics.interfaces.ros.parameters import set_run_parameters
        from mimics.interfaces.ros.scans import ScanPublisher

        super().__init__(inbox, options, sim.scenario.settings.dt, stop)
        self._sim_time_before: object = None  # /use_sim_time before the first run
        self._sim_time_set = False
        n, beams = sim.state.n, sim.types.beam_count
        self.names = RosNames(options.names, n)
        set_run_parameters(sim, options.lockstep)
        self.markers = MarkerPublisher()
        self.map = MapPublisher(sim.scenario.map, options.map_resolution)
        self.goals = GoalPublisher(sim.state.goal, self.names)
        self.clock = ClockPublisher()
        self.odometry = OdometryPublisher(sim, self.names)
        self.stalls = StallPublisher(n, self.names)
        self.frames = FramePublisher(beams, self.names, self.odometry.frames, options.map_odom)
        self.scans = ScanPublisher(sim, self.names)
        self.commands = CommandSubscriber(n, inbox, sim.scenario.settings.dt, self.names)

    def _fully_observed(self, robot: int) -> bool:
        """Whether every per-step topic of the robot has a subscriber."""
        scan = self.scans.publishers.get(robot)
        return all(publisher.get_num_connections() > 0
                   for publisher in (*self.odometry.all_publishers(robot),
                                     *([scan] if scan is not None else [])))

    def _observed(self, robot: int) -> bool:
        """Whether some node subscribes to one of the robot's per-step topics."""
        publishers = self.odometry.all_publishers(robot)
        scan = self.scans.publishers.get(robot)
        return any(publisher.get_num_connections() > 0
                   for publisher in (*publishers, *([scan] if scan is not None else [])))

    def _starting(self) -> None:
        from mimics.interfaces.ros.parameters import use_sim_time

        # before the first /clock, once the nodes the run waits for have started: a node
        # that waits on ROS time before it subscribes would otherwise wait forever
        before = use_sim_time()
        if not self._sim_time_set:  # the first run (a reset starts another)
            self._sim_time_before, self._sim_time_set = before, True

    def _commands_connected(self, robot: int) -> int:
        return self.commands.publishers_connected(robot)

    def _send(self, sim: Simulation, ids: np.ndarray) -> None:
        self.clock.publish(sim.state.time)
        self.odometry.publish(sim, ids)
        self.stalls.publish(sim, ids)
        self.scans.publish(sim, ids)
        self.frames.publish(sim, ids)
        self.markers.publish(sim)

    def close(self) -> None:
        """Withdraw every topic and subscription."""
        from mimics.interfaces.ros.parameters import clear_run_parameters, restore_sim_time

        for part in (self.commands, self.odometry, self.stalls, self.scans, self.frames,
                     self.clock, self.goals, self.map, self.markers):
            part.close()
        clear_run_parameters()
        if self._sim_time_set:
            restore_sim_time(self._sim_time_before)


def run_ros(scenario: str | Path, folder: str | Path, *, options: BridgeOptions,
            params: dict[str, Any] | None = None, time: float | None = None, seed: int = 0,
            robot_logs: RobotLogs = "auto", observers: tuple[Any, ...] = (),
            record_scans: bool = False, folders: list[Path] | None = None,
            ros_args: list[str] | None = None, stop: StopRequest | None = None) -> RunResult:
    """Run ``scenario`` as a ROS node driven by ROS controllers; record it into ``folder``.

    Args:
        scenario: a built-in scenario name or a scenario file.
        folder: the run folder.
        options: lockstep or realtime, the time-out, the map's resolution.
        params: scenario parameters (``{"robots": 5}``).
        time: simulated seconds (default: the scenario's).
        seed: the run's seed.
        robot_logs: per-robot text logs, as for ``mimics run``.
        observers: more observers of the run (a live view, say), as for ``prepare``.
        record_scans: also record the laser scans, as ``mimics run --record-scans``.
        folders: a list that receives each run's folder in order: ``folder``,
            then one per reset (``/mimics/reset``, :mod:`~mimics.interfaces.ros.services`).
        ros_args: ROS command-line arguments (remaps ``from:=to``, ``__name:=``,
            ``__ns:=``, private parameters ``_name:=value``), as rospy takes them.
        stop: where SIGINT and SIGTERM are recorded; the run then ends at the
            next step boundary with status ``interrupted`` (None: handled
            here, when called from the main thread).

    Returns:
        The outcome of the last run (the one after the last reset, if any).

    Raises:
        MimicsError: when ROS is not installed, no master answers, a scenario
            argument is bad or, in lockstep, no controller connects in time.
    """
    require_ros()
    require_master()
    import numba

    # One engine thread: the ROS round trip dominates each step, and parallel
    # kernels wake worker threads every step, which costs more than it saves
    # here and competes with the controller nodes for the cores (5 robots,
    # lockstep, loaded 2-core machine: 9.2 s of wall time with 2 threads, 1.2 to
    # 2.0 s with one).
    numba.set_num_threads(1)
    built = load_run_scenario(scenario, options, params, seed)  # stage names: robots stall
    stop = stop or StopRequest()
    with stop.handling_signals():
        return _run(built, folder, options, time, seed, robot_logs, observers, record_scans,
                    folders, ros_args, stop)


def _run(built: Any, folder: str | Path, options: BridgeOptions, time: float | None,
         seed: int, robot_logs: RobotLogs, observers: tuple[Any, ...], record_scans: bool,
         folders: list[Path] | None, ros_args: list[str] | None,
         stop: StopRequest) -> RunResult:
    """:func:`run_ros` once the scenario is built, with the signals handled."""
    import rospy

    from mimics.interfaces.ros.inbox import Inbox
    from mimics.interfaces.ros.references import RosReferences
    from mimics.interfaces.ros.services import RunControl, RunServices
    from mimics.records.runner import prepare

    inbox = Inbox(built.robot_count, options.lockstep, options.timeout, stop, options.grace)
    references = RosReferences(inbox, built.stages[:, 2], options.timeout,
                               options.timeout_option, options.watchdog)
    sim = prepare(built, references.controller(), time=time, seed=seed, observers=observers)
    join_ros(STAGE_NODE_NAME if options.names == "stage" else NODE_NAME, ros_args)
    options = private_parameters(options)
    references.watchdog = options.watchdog
    bridge = RosBridge(sim, inbox, options, stop)
    references.publishers = bridge.commands.publishers_connected
    references.names = bridge.names
    control = RunControl(options.timeout + 5.0)
    services = RunServices(control, reset_positions=options.names == "stage")

    def restart() -> Simulation:
        """After a reset: the same scenario and seed from the start."""
        again = RosReferences(inbox, built.stages[:, 2], options.timeout,
                              options.timeout_option, options.watchdog,
                              bridge.commands.publishers_connected, bridge.names)
        return prepare(built, again.controller(), time=time, seed=seed, observers=observers)

    try:
        return run_with_resets(bridge, control, sim, folder, restart, folders, stop,
                               robot_logs=robot_logs, record_scans=record_scans,
                               extra={"ros": options_record(options)})
    finally:
        control.run_ended()
        services.close()
        bridge.close()
        rospy.signal_shutdown("mimics: the run has ended")
