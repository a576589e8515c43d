"""The simulation loop (paper section 3, SPEC section 5).

Each step, for all active robots: sense (ranger, positioning, comms), run the
user's code one robot after another, apply the PID loops and the dynamics,
then check collisions, goals, escapes and stalls, and only then deactivate
(structural changes at the end of the step). Observers (logs, views) are
called after each step; the engine itself writes nothing and draws nothing.

>>> from mimics.scenarios.line import scenario
>>> from mimics.algorithms import go_to_goal
>>> sim = Simulation(scenario(robots=2), go_to_goal, seed=1)
>>> result = sim.run()
>>> result.status, result.reached_goal
('completed', 2)
"""

from __future__ import annotations

import time
import zlib
from collections.abc import Callable, Sequence
from typing import Any, Literal, Protocol

import numpy as np

from mimics.engine.collision_response import StallOnCollision
from mimics.engine.compiling import compile_seconds, heap_frozen
from mimics.engine.compiling.warm_up import load_step_kernels
from mimics.engine.deactivations import RobotDeactivations
from mimics.engine.dynamics import move_robots
from mimics.engine.edits import WorldEdits
from mimics.engine.messages import MessageBus, clear_messages
from mimics.engine.noise_streams import AlgorithmStreams, RangerNoise, StepStreams
from mimics.engine.outcome import Event, RunResult, TimingStats, result_from_state, run_digest
from mimics.engine.ranging import Scanner
from mimics.engine.robot_index import RobotIndex, index_cell, index_robots
from mimics.engine.sensors import (
    comms_matrix,
    measure_positioning,
    odometry_is_exact,
    update_odometry,
)
from mimics.engine.stall import StallDetector
from mimics.engine.state import Status, TypeArrays, WorldState
from mimics.engine.user_code import (
    Controller,
    StepTimeout,
    TeamController,
    UserFailure,
    Watchdog,
    controller_from,
    describe_timeout,
)
from mimics.world.limits import MAX_SEED, check_steps, check_whole
from mimics.world.scenario import Scenario

# plain ints: comparing arrays with an IntEnum is slow
_ESCAPED, _REMOVED = int(Status.ESCAPED), int(Status.REMOVED)

Policy = Literal["abort", "deactivate"]
POLICIES = ("abort", "deactivate")


class Observer(Protocol):
    """Something that watches a run (a logger, a live view); all hooks optional."""

    def on_start(self, sim: Simulation) -> None: ...
    def on_step(self, sim: Simulation) -> None: ...
    def on_edit(self, sim: Simulation, applied: Any) -> None: ...
    def on_end(self, sim: Simulation, result: RunResult) -> None: ...


class Simulation(RobotDeactivations, WorldEdits):
    """One run of one algorithm on one scenario with one seed.

    Args:
        scenario: the world and its robots.
        algorithm: a module, function or class following the algorithm contract
            (``mimics.engine.user_code.controllers``), or a ready ``Controller``.
        seed: seeds every random draw of the run.
        policy: on an exception in user code, ``"abort"`` ends the run with
            status ``error``; ``"deactivate"`` deactivates only that robot.
        time_limit: simulated seconds (default: the scenario's setting).
        wall_limit: wall-clock seconds after which the run stops (status ``wall_limit``);
            user code still running then is stopped (``mimics.engine.user_code.watchdog``).
        stop_when: a predicate on the simulation that ends the run when true.
        observers: objects with optional ``on_start``, ``on_step``, ``on_edit``, ``on_end``.

    The scenario's edits (``scenario.edits``) are applied at their steps, and
    ``edit`` applies one now (``mimics.engine.edits``); ``world_map`` is the
    map as edited so far, ``scenario`` the run's recipe (its first map, the edits).
    """

    def __init__(self, scenario: Scenario, algorithm: Any, seed: int = 0,
                 policy: Policy = "abort", time_limit: float | None = None,
                 wall_limit: float | None = None,
                 stop_when: Callable[[Simulation], bool] | None = None,
                 observers: Sequence[Any] = (), algorithm_name: str | None = None) -> None:
        if policy not in POLICIES:
            raise ValueError(f"policy must be one of {POLICIES}, got {policy!r}")
        self.scenario = scenario
        self.controller: Controller = controller_from(algorithm, algorithm_name)
        self.seed = check_whole("seed", seed, 0, MAX_SEED)
        self.policy = policy
        settings = scenario.settings
        self.time_limit = settings.time_limit if time_limit is None else float(time_limit)
        self.max_steps = check_steps(self.time_limit, settings.dt)
        self.wall_limit = wall_limit
        self.stop_when = stop_when
        self.observers = list(observers)
        self.types = TypeArrays.from_scenario(scenario)
        self.state = WorldState.from_scenario(scenario, self.types.beam_offsets.shape[1])
        # each sensor's noise from its own stream of the seed (noise_streams); the
        # algorithm's draws from others, one per robot and one for the team
        self.noise = {purpose: StepStreams(self.seed, purpose)
                      for purpose in ("position", "velocity", "acceleration", "odometry")}
        self._user_rngs = AlgorithmStreams(self.seed)
        self.team_memory: dict[str, Any] = {}
        self.messages = MessageBus(settings.comm_range)
        self.events: list[Event] = []
        self.timing = TimingStats()
        types = self.types
        # collisions need the walking grid; the ranger's near lists wait for a scan (walls)
        self._start_edits(scenario)
        self._robot_cell = index_cell(types.max_range, types.half_length, types.half_width)
        # fixed for the run: computed once, not at every step
        self._robot_radius = np.hypot(types.half_length, types.half_width)
        self._scanner = Scanner(self.state, types,
                                RangerNoise(self.seed),
                                lambda: self.walls, self._robot_index)
        self.status = "running"
        self.error = ""
        self.wall_time = 0.0
        self._comms: np.ndarray | None = None
        self._ever_deadlocked = np.zeros(self.state.n, dtype=bool)
        self._ever_livelocked = np.zeros(self.state.n, dtype=bool)
        self._stalls = StallDetector(settings, self.state.n)
        # None: a collision deactivates the robot (the paper's rule, the default)
        self._stall_on_collision = (StallOnCollision(self.state.n)
                                    if settings.on_collision == "stall" else None)
        self._start_goal_distance = self.state.goal_distance()
        # the kernels the steps call are loaded (compiled, on a first run) now, and the
        # rangers' walls indexed: the first step is then no slower than the next ones
        if load_step_kernels(ranging=bool(types.beam_count.any())):
            _ = self.walls
        self._grid: RobotIndex | None = None
        self._grid_key: tuple[int, bytes] | None = None
        self._pending: dict[int, Status] = {}  # deactivations applied at the end of the step
        self._started = False
        self._wall_start = 0.0
        self._watchdog: Watchdog | None = None  # only with a wall limit (watchdog.py)
        self._pose_crc = 0  # CRC-32 of every step's poses so far (run_digest)
        self._compile_start = 0.0
        self.compile_time = 0.0  # s of kernel compiles during the run, left out of wall_time
        # s the run waited between steps for whoever drives it (a live run's pacing and
        # pauses: mimics.interfaces.stepper), left out of wall_time, not of the wall limit
        self.waited = 0.0

    # -- public API ---------------------------------------------------------

    def run(self) -> RunResult:
        """Run until an end criterion holds; returns the outcome."""
        with heap_frozen():  # full collections skip the objects made before the run
            try:
                self.start()
                while self.step():
                    pass
            finally:
                self._close_watchdog()  # also when the run raises (an interrupt, a bug)
        return self.result()

    def start(self) -> None:
        """Check the initial state, call user reset hooks and observers' ``on_start``."""
        if self._started:
            return
        self._started = True
        self._wall_start = time.perf_counter()
        self._compile_start = compile_seconds()  # compiles from here on are not the run's time
        self._check_moved(np.flatnonzero(self.state.active))  # collisions only, at the start
        self._stalls.update(self.state)  # the windows start at time zero
        self._finish_deactivations()
        self._pose_crc = zlib.crc32(np.ascontiguousarray(self.state.pose).data)
        self._sense()
        if self.wall_limit is not None:  # user code that never returns is stopped
            self.controller.prepare_interrupt()
            self._watchdog = Watchdog(self.wall_limit, self._elapsed, self.controller.interrupt)
        self._handle_failures((self._guarded(None) if self._watchdog else
                               self.controller.reset(self)) or [])
        for observer in self.observers:
            if hasattr(observer, "on_start"):
                observer.on_start(self)
        self._check_end()  # also ends a run whose reset hooks failed (observers' on_end)

    def step(self) -> bool:
        """Advance one step; returns False once the run has ended."""
        if not self._started:
            self.start()
        if self.status != "running":
            return False
        if self._applied_edits < len(self.scenario.edits) and not self._apply_due_edits():
            return False  # the edits removed the last robot
        state = self.state
        active = state.active
        ids = active.nonzero()[0]  # = flatnonzero, without its Python wrappers
        clear_messages(state.user_message, active)
        clear_messages(state.system_message, active)
        compiled = compile_seconds()
        if self._watchdog is None:
            failures = self.controller.compute(self, ids)
        else:
            failures = self._guarded(ids)
            if failures is None:  # stopped past the wall limit: the run ends here
                return self._check_end()
        if compile_seconds() != compiled:  # a kernel compiled in user code's call (first scan)
            self._uncount_compile(ids, compile_seconds() - compiled)
        self.timing.add(state.user_time if ids.size == state.n else state.user_time[ids])
        failed = self._handle_failures(failures)
        moving = ids[~np.isin(ids, failed)] if failed.size else ids
        self._move(moving)
        state.step += 1
        state.time = state.step * self.scenario.settings.dt
        distance, quiet = self._check_moved(moving)  # distance: for the stall checks too
        if not quiet:
            self._mark_departures_and_arrivals(moving, distance)
        # no status changes since the top of the step (they wait in _pending)
        self._check_stalls(distance, active)
        self._finish_deactivations()
        # 48 kB for 2,000 robots: 27 us (a BLAKE2b of them: 130 us, 2% of a Hospital step)
        self._pose_crc = zlib.crc32(state.pose.data, self._pose_crc)
        self._sense()
        for observer in self.observers:
            if hasattr(observer, "on_step"):
                observer.on_step(self)
        return self._check_end()

    def result(self) -> RunResult:
        """The outcome so far (final once the run has ended)."""
        return result_from_state(
            self.state, status=self.status, scenario=self.scenario.name,
            algorithm=self.controller.name, seed=self.seed, robots=self.state.n,
            sim_time=self.state.time, wall_time=self.wall_time, steps=self.state.step,
            start_goal_distance=self._start_goal_distance,
            ever_deadlocked=self._ever_deadlocked.copy(),
            ever_livelocked=self._ever_livelocked.copy(), events=list(self.events),
            user_timing=self.timing.summary(), parameters=dict(self.scenario.parameters),
            error=self.error, trajectory_digest=self.run_digest(),
            compile_time=self.compile_time, has_goal=~np.isnan(self.state.goal[:, 0]),
            time_limit=self.time_limit, ever_stalled=None if self._stall_on_collision is None
            else self._stall_on_collision.ever.copy(),
        )

    def run_digest(self) -> str:
        """The run's digest so far (``outcome.run_digest``)."""
        return run_digest(self._pose_crc, self.state, self.status)

    def user_rng(self, robot: int | None = None) -> np.random.Generator:
        """The algorithm's generator for ``robot`` (None: the team's), its own stream of
        the seed (``AlgorithmStreams``)."""
        return self._user_rngs.get(robot)

    def comms_table(self) -> np.ndarray:
        """The communication matrix of this step (built once, on first use)."""
        if self._comms is None:
            self._comms = comms_matrix(self.state)
            self._comms.flags.writeable = False
        return self._comms

    # -- the phases of a step ----------------------------------------------

    def _solid(self) -> np.ndarray:
        """Robots that others can hit and see."""
        state = self.state
        if self.scenario.settings.inactive_as_obstacles:
            status = state.status
            return (status != _ESCAPED) & (status != _REMOVED)
        return state.active

    def _robot_index(self) -> RobotIndex:
        """Index of the solid robots; rebuilt only when poses or the solid set changed."""
        state = self.state
        solid = self._solid()
        key = (state.step, solid.tobytes())
        if self._grid_key != key:
            self._grid = index_robots(np.ascontiguousarray(state.pose[:, :2]),
                                      np.ascontiguousarray(state.pose[:, 2]),
                                      self.types.half_length, self.types.half_width, solid,
                                      self._robot_cell, self._robot_radius)
            self._grid_key = key
        return self._grid

    def _sense(self) -> None:
        """Ranger (traced when first read: ``Scanner``), positioning, comms and messages
        for the robots about to act."""
        state = self.state
        self._comms = None
        self._scanner.sense()
        measure_positioning(state, self.types, self.noise)
        self.messages.deliver(state.pose[:, :2], state.active)

    def _move(self, ids: np.ndarray) -> None:
        """PID loops and exact integration of the dynamics for robots ``ids``."""
        state, types = self.state, self.types
        state.drop_pending_scan()  # robots move now
        n = state.n
        odometer_exact = odometry_is_exact(state, types)  # checked before the pose moves
        if self._stall_on_collision is not None:  # a move that ends touching is undone
            self._stall_on_collision.remember(state)
        distance, turn = np.zeros(n), np.zeros(n)
        move_robots(ids, state.pose, state.velocity, state.acceleration, state.reference,
                    state.pid_integral, state.actuation, state.path_length, types.pid.speed,
                    types.pid.heading, *types.plant, self.scenario.settings.dt, distance, turn)
        if odometer_exact:
            # Same start, same increments, same arithmetic: the odometer would
            # compute the true pose again, bit for bit (and it draws no noise).
            state.odometry[:] = state.pose
        else:
            moved = None
            if ids.size != n:
                moved = np.zeros(n, dtype=bool)
                moved[ids] = True
            update_odometry(state, types, distance, turn, moved, self.noise["odometry"])

    def _guarded(self, ids: np.ndarray | None) -> list[UserFailure] | None:
        """The controller's ``compute(ids)`` (``reset`` for None) watched for the wall limit.

        None when it was stopped (``watchdog.py``): the run then ends at the last whole
        step, the robot whose call was stopped marked ``error`` where it was stuck."""
        watchdog = self._watchdog
        assert watchdog is not None
        try:
            watchdog.enter()
            try:
                return (self.controller.reset(self) if ids is None
                        else self.controller.compute(self, ids))
            finally:
                watchdog.leave()
        except StepTimeout as stop:
            watchdog.leave()
            state = self.state
            self.error, detail, trace = describe_timeout(stop, self.wall_limit or 0.0,
                                                         state.step, state.time)
            for robot in np.flatnonzero(state.active) if stop.robot < 0 else [stop.robot]:
                self._mark(int(robot), Status.ERROR, detail, "exception", traceback=trace)
            self._finish_deactivations()
            self.status = "wall_limit"
            return None

    def _close_watchdog(self) -> None:
        if self._watchdog is not None:
            self._watchdog.close()
            self._watchdog = None

    def _user_wants_stop(self) -> bool:
        try:
            return bool(self.stop_when(self))  # type: ignore[misc]
        except Exception as exc:  # user code: contain everything it raises
            self.status = "error"
            self.error = f"stop_when raised {type(exc).__name__}: {exc}"
            return False

    def elapsed(self) -> float:
        """Wall seconds since the run started, compiles left out and waits included (what
        the wall limit counts); 0 before the start."""
        return self._elapsed() if self._started else 0.0

    def _elapsed(self) -> float:
        """Wall seconds of the run so far, compiles (under way too) left out."""
        return (time.perf_counter() - self._wall_start
                - (compile_seconds() - self._compile_start))

    def _uncount_compile(self, ids: np.ndarray, seconds: float) -> None:
        """Take a compile out of the user code's call times: a team's call shares it out
        evenly (as its time), a robot's own call is the longest of the step."""
        times = self.state.user_time
        if isinstance(self.controller, TeamController):
            times[ids] = np.maximum(times[ids] - seconds / max(len(ids), 1), 0.0)
        elif ids.size:
            slowest = ids[int(np.argmax(times[ids]))]
            times[slowest] = max(times[slowest] - seconds, 0.0)

    def _check_end(self) -> bool:
        """Apply the end criteria; returns True while the run goes on."""
        state = self.state
        self.compile_time = compile_seconds() - self._compile_start
        elapsed = time.perf_counter() - self._wall_start - self.compile_time
        self.wall_time = elapsed - self.waited
        if self.status == "running":
            if not np.count_nonzero(state.active):
                self.status = "completed"
            elif state.step >= self.max_steps:
                self.status = "time_limit"
            elif self.wall_limit is not None and elapsed >= self.wall_limit:
                self.status = "wall_limit"
            elif self.stop_when is not None and self._user_wants_stop():
                self.status = "stopped"
        if self.status == "running":
            return True
        self._close_watchdog()
        result = self.result()
        for observer in self.observers:
            if hasattr(observer, "on_end"):
                observer.on_end(self, result)
        return False

