"""A simulation run as a ROS node: the capabilities tied to one run.

:func:`run_ros` builds the run through the ordinary runner
(``mimics.records.runner.prepare`` and ``run_to_folder``), with
:class:`RosBridge` as an observer that publishes what each step sensed, and
:class:`~mimics.interfaces.ros.references.RosReferences` as the algorithm
that returns the references received. The run folder, logs, summary and end
criteria are those of ``mimics run``.

Per step ``k`` (time ``t_k``), lockstep: the inbox is told to expect step
``k``'s commands, then ``/clock``, every active robot's ``odom``, ``pose``,
ground truth and ``scan``, and ``/tf`` are published stamped ``t_k``; the
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

import time as wall
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.interfaces.ros.names import RosNames, check_name_set
from mimics.interfaces.ros.node import NODE_NAME, STAGE_NODE_NAME, join_ros, private_parameters
from mimics.interfaces.ros.stopping import POLL, StopRequest
from mimics.interfaces.ros.stopping import STATUS as STOPPED_STATUS
from mimics.interfaces.ros.system_ros import require_master, require_ros
from mimics.world.errors import MimicsError

if TYPE_CHECKING:
    from mimics.engine.outcome import RunResult
    from mimics.engine.simulation import Simulation
    from mimics.interfaces.ros.inbox import Inbox
    from mimics.interfaces.ros.services import RunControl
    from mimics.records.recorder import RobotLogs



@dataclass(frozen=True)
class BridgeOptions:
    """How the bridge runs.

    Attributes:
        lockstep: wait each step for every active robot's command (else realtime).
        timeout: seconds to wait for the controller's nodes to connect and,
            in lockstep, for all of each step's commands (one deadline per step).
        map_resolution: metres per cell of ``/map``.
        watchdog: realtime: seconds without a command after which a robot
            is stopped (stage_ros' ``base_watchdog_timeout``).
        timeout_option: the option setting ``timeout`` in the running
            command, cited by time-out messages (None: no such option).
        names: the name set of topics and frames, ``"mimics"`` or ``"stage"``
            (see :mod:`~mimics.interfaces.ros.names`).
        grace: lockstep: seconds after which a robot whose node is alive (it
            sent a command within ``timeout``) but has not answered the step
            holds its last reference; None: strict lockstep, every step waits
            for every command (up to ``timeout``).
        startup_grace: seconds from the start during which the run waits for
            the nodes' further subscriptions (a scan subscribed after the
            odometry) before step 0; realtime: also the longest it waits for
            the nodes at all before the clock starts, as stage_ros does not wait.
    """

    lockstep: bool = True
    timeout: float = 10.0
    map_resolution: float = 0.05
    watchdog: float = 0.2
    timeout_option: str | None = "--timeout"
    names: str = "mimics"
    grace: float | None = None
    startup_grace: float = 0.0

    def __post_init__(self) -> None:
        check_name_set(self.names)
        if self.grace is not None and not self.grace > 0:
            raise MimicsError(f"grace: expected a positive number of seconds, "
                              f"got {self.grace!r}")
        if not self.startup_grace >= 0:
            raise MimicsError(f"startup_grace: expected seconds >= 0, "
                              f"got {self.startup_grace!r}")
        if not self.timeout > 0:
            raise MimicsError(f"timeout: expected a positive number of seconds, "
                              f"got {self.timeout!r}")
        if not self.watchdog > 0:
            raise MimicsError(f"watchdog: expected a positive number of seconds, "
                              f"got {self.watchdog!r}")


class RosBridge:
    """The observer that publishes a run's steps; created once ``rospy`` is initialised."""

    def __init__(self, sim: Simulation, inbox: Inbox, options: BridgeOptions,
                 stop: StopRequest | None = None) -> None:
        from mimics.interfaces.ros.clock import ClockPublisher
        from mimics.interfaces.ros.commands import CommandSubscriber
        from mimics.interfaces.ros.frames import FramePublisher
        from mimics.interfaces.ros.goals import GoalPublisher
        from mimics.interfaces.ros.grid_map import MapPublisher
        from mimics.interfaces.ros.markers import MarkerPublisher
        from mimics.interfaces.ros.odometry import OdometryPublisher
        from mimics.interfaces.ros.parameters import set_run_parameters
        from mimics.interfaces.ros.scans import ScanPublisher

        self.options = options
        self.inbox = inbox
        self.stop = stop  # a signal asked the run to end (SIGINT, SIGTERM)
        self.control: RunControl | None = None  # pause, step, reset (services.py)
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
        self.frames = FramePublisher(beams, self.names, self.odometry.frames)
        self.scans = ScanPublisher(beams, self.names)
        self.commands = CommandSubscriber(n, inbox, sim.scenario.settings.dt, self.names)
        self._dt = sim.scenario.settings.dt
        self._wall_start = 0.0

    def wait_for_nodes(self, robots: np.ndarray,
                       check: Callable[[], None] | None = None) -> None:
        """Wait until each robot's observations have a subscriber and its commands a publisher.

        A node connects to a robot by subscribing to any of its per-step
        topics (``odom``, ``pose``, the ground truth or the scan). Then, until
        ``startup_grace`` seconds from the call, the wait goes on for the
        robots' other per-step topics, so that a node that subscribes to the
        scan late in its start-up still gets step 0's. Realtime: the run
        starts after ``startup_grace`` whether the nodes have come or not.

        ``check`` is called while waiting; it raises to give up early (the
        controller's process has exited, say).

        Raises:
            MimicsError: naming the first robot still unconnected after the time-out.
        """
        start = wall.monotonic()
        deadline, grace_end = start + self.options.timeout, start + self.options.startup_grace
        waiting = robots.tolist()
        while waiting:
            self._checks(check)
            waiting = [i for i in waiting
                       if not self._observed(i) or self.commands.publishers_connected(i) == 0]
            if not waiting:
                break
            if not self.options.lockstep and wall.monotonic() >= grace_end:
                return  # realtime: the clock runs, commands apply when they come
            if wall.monotonic() > deadline:
                i = waiting[0]
                option = self.options.timeout_option
                hint = f" ({option} sets it)" if option else ""
                raise MimicsError(
                    f"no controller node for robot {i} within "
                    f"{self.options.timeout:g} s{hint} (nothing subscribes to "
                    f"{self.names.odom(i)} (or its other topics) or publishes on "
                    f"{self.names.commands_text(i)}; {len(waiting)} "
                    f"robot{'s' if len(waiting) > 1 else ''} waiting)")
            wall.sleep(0.02)
        listening = robots.tolist()
        while listening and wall.monotonic() < grace_end:
            self._checks(check)
            listening = [i for i in listening if not self._fully_observed(i)]
            wall.sleep(0.02)

    def _checks(self, check: Callable[[], None] | None) -> None:
        if check is not None:
            check()
        if self.stop is not None:
            self.stop.check()

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

    def on_start(self, sim: Simulation) -> None:
        from mimics.interfaces.ros.parameters import use_sim_time

        # before the first /clock, once the nodes the run waits for have started: a node
        # that waits on ROS time before it subscribes would otherwise wait forever
        before = use_sim_time()
        if not self._sim_time_set:  # the first run (a reset starts another)
            self._sim_time_before, self._sim_time_set = before, True
        self._wall_start = wall.monotonic()
        self._publish(sim)

    def on_step(self, sim: Simulation) -> None:
        if self.stop is not None and self.stop.requested:
            # at this step boundary: the engine ends the run and writes its summary
            sim.status = STOPPED_STATUS
            return
        if self.control is not None:
            publish, held = self.control.gate()  # paused: held here, before publishing
            self._wall_start += held  # realtime: simulated time stood still meanwhile
            if not publish:  # a reset ends the run (its stop_when)
                return
        self._publish(sim)

    def on_end(self, sim: Simulation, result: RunResult) -> None:
        self.inbox.stop()

    def _publish(self, sim: Simulation) -> None:
        state = sim.state
        ids = np.flatnonzero(state.active)
        self.inbox.now = state.time  # the watchdog counts simulated time, as stage_ros
        if self.options.lockstep:
            self.inbox.expect(state.step, ids)  # before publishing: no answer can come earlier
        self.clock.publish(state.time)
        self.odometry.publish(sim, ids)
        self.scans.publish(sim, ids)
        self.frames.publish(sim, ids)
        self.markers.publish(sim)
        if self.control is not None:
            self.control.published(state.step, state.time)
        if not self.options.lockstep:  # realtime: the next step happens dt later
            self._sleep_until(self._wall_start + state.time + self._dt)

    def _sleep_until(self, moment: float) -> None:
        """Sleep until wall time ``moment``, in short slices: a stop ends the wait."""
        while (pause := moment - wall.monotonic()) > 0:
            if self.stop is not None and self.stop.requested:
                return
            wall.sleep(min(pause, POLL))

    def close(self) -> None:
        """Withdraw every topic and subscription."""
        from mimics.interfaces.ros.parameters import clear_run_parameters, restore_sim_time

        for part in (self.commands, self.odometry, self.scans, self.frames, self.clock,
                     self.goals, self.map, self.markers):
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

    from mimics.catalog import load_scenario

    # One engine thread: the ROS round trip dominates each step, and parallel
    # kernels wake worker threads every step, which costs more than it saves
    # here and competes with the controller nodes for the cores (5 robots,
    # lockstep, loaded 2-core machine: 9.2 s of wall time with 2 threads, 1.2 to
    # 2.0 s with one).
    numba.set_num_threads(1)
    built = load_scenario(scenario, run_seed=seed, **(params or {}))
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
    from mimics.records.runner import prepare, run_to_folder

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
    control = bridge.control = RunControl(options.timeout + 5.0)
    control.stop_request = stop
    services = RunServices(control, reset_positions=options.names == "stage")
    extra = {"ros": {"mode": "lockstep" if options.lockstep else "realtime",
                     "timeout": options.timeout, "watchdog": options.watchdog,
                     "grace": options.grace, "startup_grace": options.startup_grace,
                     "names": options.names, "map_resolution": options.map_resolution}}
    first = folder = Path(folder)
    try:
        bridge.wait_for_nodes(np.flatnonzero(sim.state.active))
        while True:
            sim.observers.append(bridge)
            sim.stop_when = control.reset_asked  # a reset ends the run (status "stopped")
            control.run_started(folder)
            if folders is not None:
                folders.append(folder)
            result = run_to_folder(sim, folder, robot_logs=robot_logs,
                                   record_scans=record_scans, extra=extra)
            if not control.reset_asked() or stop.requested:
                return result
            # a reset: the same scenario and seed from the start, in a new folder
            folder = control.next_reset_folder(first)
            references = RosReferences(inbox, built.stages[:, 2], options.timeout,
                                       options.timeout_option, options.watchdog,
                                       bridge.commands.publishers_connected, bridge.names)
            sim = prepare(built, references.controller(), time=time, seed=seed,
                          observers=observers)
    finally:
        control.run_ended()
        services.close()
        bridge.close()
        rospy.signal_shutdown("mimics: the run has ended")
