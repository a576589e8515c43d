"""A compiled algorithm as a :class:`~mimics.engine.user_code.controllers.Controller`.

``mimics_step`` runs for every active robot in one call into the host code
(``host.c``), which fills each robot's ``mimics_robot`` from the world's
arrays and times each call on its own, as the Python per-robot form does.
``mimics_team_step`` goes through the Python team form: it is handed the
same arrays as ``team`` (``mimics.engine.user_code.robot_view.Team``).

Failures follow the contract of ``controllers.py``: a non-zero return code
or a non-finite reference is recorded against the robot and handled by the
run's policy. A crash (a segfault) takes the process with it: batteries
record it as ``crashed`` and ``mimics run`` runs such files in a child
process (``mimics.interfaces.cli.native``). A call still running past a
run's wall limit is cut: the watchdog (``mimics.engine.user_code.watchdog``) sends
:data:`CUT_SIGNAL` to the thread running it, whose handler in ``host.c``
jumps back to the host; the run then ends as a Python step stopped there.
"""

from __future__ import annotations

import os
import signal
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.user_code import (
    Controller,
    Robot,
    StepTimeout,
    Team,
    TeamController,
    UserFailure,
)
from mimics.native.build import NativeBuild, load_native
from mimics.world.errors import AlgorithmError

if TYPE_CHECKING:
    from mimics.engine.simulation import Simulation

#: Environment variable naming a file of two int64 (robot being called, step) that
#: the host keeps up to date, so that a parent process can say where a crash happened.
PROGRESS_ENV = "MIMICS_NATIVE_PROGRESS"

_STEP, _RESET, _TEAM_STEP, _TEAM_RESET = 1, 2, 4, 8  # mimics_host_entry_points() bits
_ERROR, _NOT_FINITE, _LOG, _SENT = 1, 2, 4, 8  # flags of mimics_host_run, as in host.c
_BROADCAST = -1
#: The C pointer type of each world array's dtype (cffi casts the buffer; no copy).
_POINTER = {"int64": "int64_t *", "float64": "double *", "bool": "unsigned char *"}
#: The signal that cuts a compiled call running past the wall limit (its handler is
#: installed by runs with a wall limit only).
CUT_SIGNAL = getattr(signal, "SIGUSR2", 0)


class NativeError(Exception):
    """A compiled entry point returned a non-zero code."""


def native_controller(path: str | Path, name: str | None = None) -> Controller:
    """Compile (or find in the cache) a C/C++ algorithm file and wrap it as a controller.

    A file defining ``mimics_team_step`` is a team algorithm, else it needs
    ``mimics_step``.

    Raises:
        AlgorithmError: neither entry point, a compile error, or another ABI.
    """
    build = load_native(path)
    label = name or Path(path).name
    entries = build.lib.mimics_host_entry_points()
    if entries & _TEAM_STEP:
        team = NativeTeam(build)
        return NativeTeamController(build, label, team_step=team.team_step,
                                    reset=team.team_reset)
    if entries & _STEP:
        return NativeRobotController(build, label)
    raise AlgorithmError(f"{path}: define int mimics_step(const mimics_robot *robot, "
                         "mimics_output *out) or int mimics_team_step(const mimics_team *team, "
                         "double *speed, double *heading) (see mimics.h)")


def _arm_cuts(build: NativeBuild) -> None:
    """Install the handler that cuts this build's calls (see ``host.c``)."""
    if not CUT_SIGNAL or build.lib.mimics_host_arm_cuts(int(CUT_SIGNAL)) != 0:
        raise AlgorithmError(f"{build.source}: cannot install the handler that stops a call "
                             "running past the wall limit on this system")


def _cut(thread_id: int) -> None:
    """Cut the compiled call running in thread ``thread_id`` (ignored between calls)."""
    signal.pthread_kill(thread_id, CUT_SIGNAL)


def _was_cut(build: NativeBuild, robot: int, entry: str) -> StepTimeout:
    """The exception saying that ``robot``'s call of ``entry`` was cut (-1: the team's)."""
    stop = StepTimeout()
    stop.robot, stop.entry = robot, f"{entry} in {build.source.name}"
    return stop


def _progress_buffer() -> np.ndarray:
    """Where the host notes the robot it is calling: a shared file when asked, else memory."""
    path = os.environ.get(PROGRESS_ENV)
    if path:
        return np.memmap(path, dtype=np.int64, mode="r+", shape=(2,))
    return np.full(2, -1, dtype=np.int64)


def _message_bytes(message: Any) -> bytes:
    """A message as the bytes a C inbox holds (C senders send bytes already)."""
    if isinstance(message, bytes | bytearray | memoryview):
        return bytes(message)
    return str(message).encode("utf-8")


class NativeRobotController(Controller):
    """Calls ``mimics_step`` for each robot in turn, all of a step in one call to C."""

    def __init__(self, build: NativeBuild, name: str) -> None:
        self.name = name
        self._build = build
        self._ffi, self._lib = build.ffi, build.lib
        self._has_reset = bool(build.lib.mimics_host_entry_points() & _RESET)
        self._keep: dict[str, Any] = {}  # arrays whose memory C points to, kept alive
        self._pointed: dict[str, np.ndarray] = {}
        self._sent = False
        self._inboxes: list[int] = []

    def prepare_interrupt(self) -> None:
        _arm_cuts(self._build)

    def interrupt(self, thread_id: int) -> None:
        _cut(thread_id)

    def reset(self, sim: Simulation) -> list[UserFailure]:
        ffi, lib = self._ffi, self._lib
        n = sim.state.n
        self._robots = ffi.new("mimics_robot[]", max(n, 1))
        self._outputs = ffi.new("mimics_output[]", max(n, 1))
        block = int(lib.MIMICS_MEMORY_BYTES)
        memory = np.zeros(max(n, 1) * block // 8 + 8)  # float64: 8-byte aligned blocks
        base = ffi.cast("char *", ffi.from_buffer(memory))
        for i in range(n):
            self._robots[i].memory = base + i * block
        self._flags = np.zeros(max(n, 1), dtype=np.int32)
        self._codes = np.zeros(max(n, 1), dtype=np.int32)
        self._progress = _progress_buffer()
        self._world = ffi.new("mimics_host_world *")
        world, types = self._world, sim.types
        world.beams = types.beam_offsets.shape[1]
        world.dt = sim.scenario.settings.dt
        world.comm_range = sim.scenario.settings.comm_range
        scratch = np.zeros(max(n, 1) * 6)
        self._keep = {"memory": memory, "scratch": scratch}
        world.comms_scratch = ffi.cast("double *", ffi.from_buffer(scratch))
        world.current = ffi.cast("int64_t *", ffi.from_buffer(self._progress))
        self._pointed = {}
        self._sent = False
        self._inboxes = []
        if not self._has_reset:
            return []
        return self._call(sim, np.flatnonzero(sim.state.active), reset=True)

    def compute(self, sim: Simulation, ids: np.ndarray) -> list[UserFailure]:
        return self._call(sim, ids, reset=False)

    def _call(self, sim: Simulation, ids: np.ndarray, reset: bool) -> list[UserFailure]:
        ffi = self._ffi
        state = sim.state
        self._point_world(sim)
        self._world.time = state.time
        table = sim.comms_table()
        self._keep["comms"] = table
        self._world.comms = ffi.cast("double *", ffi.from_buffer(table))
        self._world.comms_count = len(table)
        self._fill_inboxes(sim, ids)
        ids = np.ascontiguousarray(ids, dtype=np.int64)
        self._progress[1] = state.step
        flagged = self._lib.mimics_host_run(
            self._world, self._robots, self._outputs, ffi.cast("int64_t *", ffi.from_buffer(ids)),
            len(ids), int(reset), ffi.cast("int *", ffi.from_buffer(self._flags)),
            ffi.cast("int *", ffi.from_buffer(self._codes)))
        if not flagged:
            return []
        if flagged < 0 and self._lib.mimics_host_was_cut():  # past the wall limit
            robot = int(self._progress[0])
            self._progress[0] = -1
            raise _was_cut(self._build, robot, "mimics_reset" if reset else "mimics_step")
        return self._flagged(sim, ids, reset)

    def _point_world(self, sim: Simulation) -> None:
        """Point the host at the world's arrays (again only if one was replaced)."""
        state, types = sim.state, sim.types
        arrays = {
            "measured_pose": state.measured_pose, "pose": state.pose,
            "measured_velocity": state.measured_velocity, "velocity": state.velocity,
            "measured_acceleration": state.measured_acceleration, "odometry": state.odometry,
            "goal": state.goal, "scan": state.scan, "beam_offsets": types.beam_offsets,
            "beam_count": types.beam_count, "max_range": types.max_range,
            "half_length": types.half_length, "half_width": types.half_width,
            "kv": types.plant.kv, "stalled": state.stalled, "reference": state.reference,
            "user_time": state.user_time}
        ffi = self._ffi
        for field, array in arrays.items():
            if self._pointed.get(field) is array:
                continue
            if not array.flags.c_contiguous:
                raise AlgorithmError(f"native algorithm: world array {field} is not contiguous")
            pointer = ffi.cast(_POINTER[array.dtype.name], ffi.from_buffer(array))
            setattr(self._world, field, pointer)
            self._pointed[field] = array

    def _fill_inboxes(self, sim: Simulation, ids: np.ndarray) -> None:
        """Messages sent last step (only this algorithm sends) as each robot's C inbox."""
        for i in self._inboxes:
            self._robots[i].inbox_count = 0
        self._inboxes = []
        self._keep.pop("inbox", None)
        if not self._sent:
            return
        self._sent = False
        ffi, kept = self._ffi, []
        for i in ids.tolist():
            received = sim.messages.inbox(i)
            if not received:
                continue
            entries = ffi.new("mimics_message[]", len(received))
            for k, (sender, message) in enumerate(received):
                data = _message_bytes(message)
                entries[k].sender = int(sender)
                entries[k].size = len(data)
                buffer = ffi.from_buffer(data)
                entries[k].data = ffi.cast("unsigned char *", buffer)
                kept.append(buffer)
            kept.append(entries)
            self._robots[i].inbox = entries
            self._robots[i].inbox_count = len(received)
            self._inboxes.append(i)
        self._keep["inbox"] = kept

    def _flagged(self, sim: Simulation, ids: np.ndarray, reset: bool) -> list[UserFailure]:
        """Logs, messages and failures of the calls the host flagged."""
        ffi = self._ffi
        now = sim.state.time
        entry = "mimics_reset" if reset else "mimics_step"
        failures = []
        for j in np.flatnonzero(self._flags[: len(ids)]).tolist():
            i, flag, out = int(ids[j]), int(self._flags[j]), self._outputs[int(ids[j])]
            text = ""
            if flag & _LOG:
                text = ffi.string(out.log, out.log_size).decode("utf-8", "replace")
                Robot(sim, i).log(text)
            if flag & _SENT:
                for k in range(out.outbox_count):
                    message = out.outbox[k]
                    data = bytes(ffi.buffer(message.data, message.size))
                    sim.messages.send(i, data, None if message.to == _BROADCAST else message.to)
                self._sent = True
            if flag & _ERROR:
                code = int(self._codes[j])
                detail = (f"robot {i}: {entry} returned {code} at step {sim.state.step}"
                          + (f": {text}" if text else ""))
                failures.append(UserFailure(i, now, "NativeError", detail, ""))
            elif flag & _NOT_FINITE:
                failures.append(UserFailure(
                    i, now, "InvalidOutput", f"robot {i}: {entry} returned a non-finite "
                    f"reference (speed_ref={out.speed}, heading_ref={out.heading})", ""))
        return failures


class NativeTeamController(TeamController):
    """The team form of a compiled algorithm: ``TeamController`` whose calls are cut by a
    signal at the wall limit."""

    def __init__(self, build: NativeBuild, name: str, **hooks: Any) -> None:
        super().__init__(name, **hooks)
        self._build = build

    def prepare_interrupt(self) -> None:
        _arm_cuts(self._build)

    def interrupt(self, thread_id: int) -> None:
        _cut(thread_id)


class NativeTeam:
    """``mimics_team_step`` as a Python ``team_step(team)`` for ``TeamController``."""

    def __init__(self, build: NativeBuild) -> None:
        self._build = build
        self._ffi, self._lib = build.ffi, build.lib
        self._key = f"mimics.native.{build.folder.name}"

    def team_reset(self, team: Team) -> None:
        """Zero the team's memory block, then call ``mimics_team_reset`` if defined."""
        memory = np.zeros(int(self._lib.MIMICS_TEAM_MEMORY_BYTES) // 8)
        team.memory[self._key] = memory
        self._call(team, reset=True)

    def team_step(self, team: Team) -> tuple[np.ndarray, np.ndarray]:
        """One call of ``mimics_team_step`` for the whole team."""
        return self._call(team, reset=False)

    def _call(self, team: Team, reset: bool) -> tuple[np.ndarray, np.ndarray]:
        ffi = self._ffi
        memory = team.memory.get(self._key)
        if memory is None:  # a team_step without team_reset (not through TeamController)
            memory = team.memory[self._key] = np.zeros(
                int(self._lib.MIMICS_TEAM_MEMORY_BYTES) // 8)
        angles = np.ascontiguousarray(team.scan.angles, dtype=np.float64)
        arrays = {
            "ids": np.ascontiguousarray(team.ids, dtype=np.int64),
            "pose": team.pose, "true_pose": team.true_pose, "velocity": team.velocity,
            "odometry": team.odometry, "goal": team.goal, "ranges": team.scan.ranges,
            "angles": angles,
            "beam_count": np.count_nonzero(~np.isnan(angles), axis=1).astype(np.int64),
            "max_range": team.scan.max_range, "max_speed": team.max_speed,
            "length": team.length, "width": team.width, "comms": team.comms,
            "stalled": np.asarray(team.stalled, dtype=np.int64)}
        struct = ffi.new("mimics_team *")
        kept = []
        for field, array in arrays.items():
            array = np.ascontiguousarray(array)
            kept.append(array)
            kind = "int64_t *" if array.dtype == np.int64 else "double *"
            setattr(struct, field, ffi.cast(kind, ffi.from_buffer(array)))
        struct.count = len(team.ids)
        struct.beams = angles.shape[1] if angles.ndim == 2 else 0
        struct.time, struct.dt = team.time, team.dt
        struct.comms_count = len(arrays["comms"])
        struct.memory = ffi.cast("void *", ffi.from_buffer(memory))
        speed = np.full(len(team.ids), np.nan)
        heading = np.full(len(team.ids), np.nan)
        code = self._lib.mimics_host_team(struct, ffi.cast("double *", ffi.from_buffer(speed)),
                                          ffi.cast("double *", ffi.from_buffer(heading)),
                                          int(reset))
        if code != 0:
            entry = "mimics_team_reset" if reset else "mimics_team_step"
            if self._lib.mimics_host_was_cut():  # past the wall limit
                raise _was_cut(self._build, -1, entry)
            raise NativeError(f"{entry} returned {code} at step {round(team.time / team.dt)}")
        return speed, heading
