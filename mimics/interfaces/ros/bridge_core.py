"""The bridge core every transport shares: options, the wait for the nodes, lockstep and pace.

:class:`BridgeCore` is the run's observer for ROS 1 (``rospy``,
:class:`~mimics.interfaces.ros.bridge.RosBridge`) and ROS 2 (Cyclone DDS,
:class:`~mimics.interfaces.ros2.bridge.Ros2Bridge`): per step it tells the
inbox which step the commands must answer (lockstep), has the transport
publish the step's observations, and in realtime sleeps until the next
step's wall time; a pause (``control``) holds the step, a stop request ends
the run at the step boundary. Before step 0, :meth:`BridgeCore.wait_for_nodes`
waits for the controller's nodes. A transport supplies only the four hooks:
``_send`` (the step's messages), ``_observed``, ``_fully_observed`` and
``_commands_connected`` (what its middleware says of the connections).

What the messages say is decided here and in
:mod:`~mimics.interfaces.ros.readings`, not in the transports: whether
``/tf`` carries ``map -> odom`` (:attr:`BridgeOptions.map_odom`), and which
robots publish (:func:`published_robots`: under the ``stage`` names, a robot
that reached its goal or collided stays and goes on publishing, still, as a
Stage robot does), and what a collision does (:func:`load_run_scenario`: under
the ``stage`` names the robot stalls, as in Stage, unless the scenario says).
"""

from __future__ import annotations

import time as wall
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.state import Status
from mimics.interfaces.ros.names import RosNames, check_name_set
from mimics.interfaces.ros.stopping import POLL, StopRequest
from mimics.interfaces.ros.stopping import STATUS as STOPPED_STATUS
from mimics.world.errors import MimicsError

if TYPE_CHECKING:
    from mimics.engine.outcome import RunResult
    from mimics.engine.simulation import Simulation
    from mimics.interfaces.ros.inbox import Inbox
    from mimics.interfaces.ros.run_control import RunControl
    from mimics.world.scenario import Scenario


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
        publish_map_odom: whether ``/tf`` carries each robot's ``map -> odom``
            (the correction a localiser publishes); None: yes under the
            ``mimics`` names (RViz shows the robots in ``map``), no under
            ``stage`` (stage_ros publishes none: it would fight ``amcl``).
    """

    lockstep: bool = True
    timeout: float = 10.0
    map_resolution: float = 0.05
    watchdog: float = 0.2
    timeout_option: str | None = "--timeout"
    names: str = "mimics"
    grace: float | None = None
    startup_grace: float = 0.0
    publish_map_odom: bool | None = None

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
        if self.publish_map_odom is not None and not isinstance(self.publish_map_odom, bool):
            raise MimicsError(f"publish_map_odom: expected true, false or None (the name "
                              f"set's default), got {self.publish_map_odom!r}")

    @property
    def map_odom(self) -> bool:
        """Whether ``/tf`` carries ``map -> odom`` (:attr:`publish_map_odom` resolved)."""
        if self.publish_map_odom is not None:
            return self.publish_map_odom
        return self.names != "stage"

    @property
    def stopped_robots_publish(self) -> bool:
        """Whether robots that stopped (goal, collision...) go on publishing, still, as
        Stage's robots stay in its world: under the ``stage`` names."""
        return self.names == "stage"


class BridgeCore(ABC):
    """The observer that publishes a run's steps through a transport (see the module)."""

    names: RosNames

    def __init__(self, inbox: Inbox, options: BridgeOptions, dt: float,
                 stop: StopRequest | None = None) -> None:
        self.options = options
        self.inbox = inbox
        self.stop = stop  # a signal asked the run to end (SIGINT, SIGTERM)
        self.control: RunControl | None = None  # pause, step, reset (services.py)
        self._dt = dt
        self._wall_start = 0.0

    @abstractmethod
    def _send(self, sim: Simulation, ids: np.ndarray) -> None:
        """Publish the current step's clock, and the observations and frames of robots
        ``ids`` (:func:`published_robots`: under the ``stage`` names, stopped robots
        too), and the markers."""

    @abstractmethod
    def _observed(self, robot: int) -> bool:
        """Whether some node subscribes to one of the robot's per-step topics."""

    @abstractmethod
    def _fully_observed(self, robot: int) -> bool:
        """Whether every per-step topic of the robot has a subscriber."""

    @abstractmethod
    def _commands_connected(self, robot: int) -> int:
        """How many publishers of the robot's commands are connected."""

    @abstractmethod
    def _starting(self) -> None:
        """Before step 0's messages, once the nodes have come (``/use_sim_time``, say)."""

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
                       if not self._observed(i) or self._commands_connected(i) == 0]
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

    def on_start(self, sim: Simulation) -> None:
        self._starting()
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
        self._send(sim, published_robots(state.status, self.options))
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


def published_robots(status: np.ndarray, options: BridgeOptions) -> np.ndarray:
    """The robots whose observations a step publishes: the active ones; under the
    ``stage`` names also those that stopped (goal reached, collided...), which stay in
    the world as Stage's do, but not those an edit took out of it."""
    if options.stopped_robots_publish:
        return np.flatnonzero(status != Status.REMOVED)
    return np.flatnonzero(status == Status.ACTIVE)


def load_run_scenario(scenario: str | Path, options: BridgeOptions,
                      params: dict[str, Any] | None, seed: int) -> Scenario:
    """The run's scenario (``mimics.catalog.load_scenario``). Under the ``stage`` names,
    :data:`STAGE_SETTINGS`: a robot that bumps into a wall or a robot stalls there and
    stays, as Stage's do, and no robot is removed for waiting, unless ``params`` or the
    scenario file's ``[settings]`` say otherwise (a Python scenario:
    ``--param on_collision=deactivate``, ``--param deactivate_on_deadlock=true``).
    """
    from dataclasses import replace

    from mimics.catalog import load_scenario

    params = dict(params or {})
    built = load_scenario(scenario, run_seed=seed, **params)
    if options.names != "stage":
        return built
    stage = {name: value for name, value in STAGE_SETTINGS.items()
             if name not in params and not _file_sets(name, scenario)}
    # recorded among the parameters too: the summary says how the run was made
    return replace(built.with_settings(**stage), parameters={**built.parameters, **stage})


#: What a Stage world does that mimics' defaults do not, set under the stage names unless
#: the run's parameters or its scenario file's [settings] say otherwise: a robot that
#: bumps stalls and stays; nothing removes a robot that waits (Stage has no deadlock rule).
STAGE_SETTINGS: dict[str, Any] = {"on_collision": "stall", "deactivate_on_deadlock": False}


def _file_sets(setting: str, scenario: str | Path) -> bool:
    """Whether ``scenario`` is a TOML file whose ``[settings]`` table gives ``setting``."""
    if not str(scenario).endswith(".toml"):
        return False
    import tomllib

    with open(scenario, "rb") as file:  # load_scenario has read it already: it parses
        table = tomllib.load(file).get("settings")
    return isinstance(table, dict) and setting in table


def options_record(options: BridgeOptions) -> dict[str, Any]:
    """What the summary records of the bridge's options (its ``ros``/``ros2`` entry)."""
    return {"mode": "lockstep" if options.lockstep else "realtime",
            "timeout": options.timeout, "watchdog": options.watchdog,
            "grace": options.grace, "startup_grace": options.startup_grace,
            "names": options.names, "map_resolution": options.map_resolution,
            "publish_map_odom": options.map_odom,
            "stopped_robots_publish": options.stopped_robots_publish}


def run_with_resets(bridge: BridgeCore, control: RunControl, sim: Simulation,
                    folder: str | Path, restart: Callable[[], Simulation],
                    folders: list[Path] | None, stop: StopRequest,
                    **recording: Any) -> RunResult:
    """Wait for the nodes, then run ``sim`` into ``folder`` with ``bridge`` observing it;
    after each reset (``control``), run ``restart()``'s simulation into the next
    ``FOLDER-reset-K``. ``recording``: ``run_to_folder``'s options.

    Returns:
        The outcome of the last run.
    """
    from mimics.records.runner import run_to_folder

    first = folder = Path(folder)
    control.stop_request = stop
    bridge.control = control
    bridge.wait_for_nodes(np.flatnonzero(sim.state.active))
    while True:
        sim.observers.append(bridge)
        sim.stop_when = control.reset_asked  # a reset ends the run (status "stopped")
        control.run_started(folder)
        if folders is not None:
            folders.append(folder)
        result = run_to_folder(sim, folder, **recording)
        if not control.reset_asked() or stop.requested:
            return result
        # a reset: the same scenario and seed from the start, in a new folder
        folder = control.next_reset_folder(first)
        sim = restart()
