"""The server's side of live runs: one worker process each, its state, its frames, its watchers.

A :class:`LiveRun` starts :func:`mimics.interfaces.web.live_worker.worker_main` in a
process of its own (spawn: no copy of the server's threads or sockets), sends it
commands and edits, and reads what it streams in a thread of the server: the
latest frame, the meta (map, goals, robot sizes), and the end. Pages watching
the run (:meth:`LiveRun.watch`) are woken from that thread for each new frame;
each page sends only the latest frame when it is ready for one, so a slow page
drops frames instead of slowing the run or the other pages. Closing a page
never stops the run.

Stop answers once the run has ended (its state ``finished`` or ``error``), or,
should its last step take longer than a few seconds, ``stopping``. The
inspector's reads of a run that has just ended (``robot``, ``beams``) are
answered from its final state rather than refused: a page's request in flight
at the end is no error.
"""

from __future__ import annotations

import asyncio
import contextlib
import itertools
import multiprocessing
import threading
import time
from typing import Any

import numpy as np

from mimics.interfaces.web.live_frames import STATE_NAMES
from mimics.interfaces.web.live_worker import STOP_WAIT, worker_main

#: Seconds a command may take in the worker (a Step waits for its step).
COMMAND_TIMEOUT = 40.0
#: Seconds an edit may wait for its step boundary.
EDIT_TIMEOUT = 60.0
#: Seconds to wait for the worker to prepare the run (imports, scenario, kernels).
START_TIMEOUT = 300.0
#: Seconds a run may take to end after Stop before its worker is ended (a step that never
#: returns: the folder then keeps what was recorded, without summary.json).
STOP_GRACE = 10.0
#: Live runs going at once at most (each is a process stepping on a core).
MAX_RUNNING = 4
ENDED = ("finished", "error")


class LiveRefused(Exception):
    """A request the live run cannot honour: an HTTP status and one line."""

    def __init__(self, status: int, message: str) -> None:
        super().__init__(message)
        self.status = status


class LiveRun:
    """One live run: its worker process and what the server knows of it.

    Attributes:
        id: its number in this server.
        state: ``starting``, ``running``, ``paused``, ``stopping`` (Stop asked, the last
            step not done yet), ``finished`` or ``error``.
        step, time: the last step taken (from the worker's frames and answers).
        speed: simulated seconds per wall second (``inf``: as fast as possible).
        run: the run folder (real path), once the worker made it.
        status: the simulation's end status (``time_limit``, ``stopped``...), once ended.
        error: one line when the run could not start or ended in error.
        meta: the map, goals, robot sizes and colours of the latest ``meta`` message.
        frame: the latest frame body (the replay's layout, one frame).
        moves: ``(robot, step)`` of each move by an edit, in order (for the trails).
    """

    def __init__(self, run_id: int, request: dict[str, Any], label: dict[str, Any]) -> None:
        self.id = run_id
        self.label = label
        self.state = "starting"
        self.step = 0
        self.time = 0.0
        self.speed = float(request["speed"])
        self.run = ""
        self.status = ""
        self.error = ""
        self.meta: dict[str, Any] = {}
        self.meta_version = 0
        self.frame: bytes | None = None
        self.frame_version = 0
        self.moves: list[tuple[int, int]] = []  # (robot, step) of each robot an edit moved
        self.started = time.time()
        self._lock = threading.Lock()
        self._control_lock = threading.Lock()
        self._edit_lock = threading.Lock()
        self._ready = threading.Event()
        self._ended = threading.Event()  # the worker's end came (or the worker died)
        self._robots: dict[int, dict[str, Any]] = {}  # the inspector's last answer per robot
        self._watchers: set[tuple[asyncio.AbstractEventLoop, asyncio.Event]] = set()
        context = multiprocessing.get_context("spawn")
        self._control, control_end = context.Pipe()
        self._edits, edits_end = context.Pipe()
        self._stream, stream_end = context.Pipe(duplex=False)
        self.process = context.Process(target=worker_main, name=f"mimics-live-{run_id}",
                                       args=(request, control_end, edits_end, stream_end),
                                       daemon=True)
        self.process.start()
        for end in (control_end, edits_end, stream_end):  # the worker's ends: EOF when it dies
            end.close()
        threading.Thread(target=self._read, name=f"mimics-live-read-{run_id}",
                         daemon=True).start()

    # -- what the worker sends ------------------------------------------------------------

    def wait_ready(self, timeout: float = START_TIMEOUT) -> None:
        """Wait until the worker has prepared the run (or failed to)."""
        self._ready.wait(timeout)

    def _read(self) -> None:
        while True:
            try:
                message = self._stream.recv()
            except (EOFError, OSError):
                break
            self._take(message)
        self.process.join(5.0)
        with self._lock:
            if self.state not in ENDED:
                self.state = "error"
                self.error = self.error or (f"the live run's worker ended unexpectedly (exit "
                                            f"code {self.process.exitcode})")
        self._ready.set()
        self._ended.set()
        self._notify()

    def _take(self, message: tuple[Any, ...]) -> None:
        kind = message[0]
        with self._lock:
            if kind == "frame":
                _, step, sim_time, body = message
                if step >= self.step or self.frame is None:
                    self.step, self.time, self.frame = step, sim_time, body
                    self.frame_version += 1
            elif kind == "meta":
                self.meta = message[1]
                self.meta_version += 1
            elif kind == "moved":
                self.moves.append((int(message[1]), int(message[2])))
            elif kind == "ready":
                info = message[1]
                self.run, self.meta, self.speed = info["run"], info["meta"], info["speed"]
                self.meta_version += 1
                self.state = "paused" if self.label.get("started_paused") else "running"
            elif kind == "failed":
                self.state, self.error = "error", message[1]
            elif kind == "end":
                info = message[1]
                self.status, self.error = info["status"], info["error"]
                self.step, self.time = info["step"], info["time"]
                self.state = "error" if info["error"] or info["status"] == "error" \
                    else "finished"
        if kind in ("ready", "failed"):
            self._ready.set()
        if kind == "end":
            self._ended.set()
        self._notify()

    # -- watchers (pages) -----------------------------------------------------------------

    def watch(self) -> asyncio.Event:
        """An event set whenever a frame, the meta or the state changes (call from the
        event loop of the page's connection)."""
        event = asyncio.Event()
        with self._lock:
            self._watchers.add((asyncio.get_running_loop(), event))
        event.set()  # the page gets what there is at once
        return event

    def unwatch(self, event: asyncio.Event) -> None:
        """Stop waking ``event`` (the page's connection closed)."""
        with self._lock:
            self._watchers = {w for w in self._watchers if w[1] is not event}

    @property
    def watchers(self) -> int:
        """Pages watching now."""
        return len(self._watchers)

    def _notify(self) -> None:
        with self._lock:
            watchers = list(self._watchers)
        for loop, event in watchers:
            with contextlib.suppress(RuntimeError):  # that page's loop has closed
                loop.call_soon_threadsafe(event.set)

    # -- commands ---------------------------------------------------------------------------

    def robot(self, i: int) -> dict[str, Any]:
        """Robot ``i`` now (the inspector's fields and its events so far); once the run
        has ended, as last seen (``final``: true).

        Raises:
            LiveRefused: as :meth:`command` while the run starts; 422 when there is no
                robot ``i``.
        """
        if not self._final():
            try:
                answer: dict[str, Any] = self._ask("robot", i)["robot"]
            except LiveRefused as refusal:
                if refusal.status != 409 or not self._final():
                    raise
            else:
                self._robots[i] = answer
                return answer
        return self._final_robot(i)

    def beams(self, robot: int | None) -> dict[str, Any]:
        """The beams of robot ``robot``'s last scan (None: every active robot's), as the
        worker's ``beams`` answers; once the run has ended, none (``final``: true: the
        page keeps those it drew).

        Raises:
            LiveRefused: as :meth:`command` while the run starts; 422 when there is no
                robot ``robot``.
        """
        if not self._final():
            try:
                beams: dict[str, Any] = self._ask("beams", "all" if robot is None
                                                  else robot)["beams"]
                return beams
            except LiveRefused as refusal:
                if refusal.status != 409 or not self._final():
                    raise
        self._check_robot(robot)
        return {"segments": [], "every": 1, "step": self.step, "time": self.time,
                "final": True}

    def _final(self) -> bool:
        """True once the run has ended or is ending (its worker answers no more reads)."""
        return self.state in (*ENDED, "stopping") or self._ended.is_set()

    def _check_robot(self, i: int | None) -> None:
        robots = int(self.meta.get("robots", 0))
        if i is not None and not 0 <= i < robots:
            raise LiveRefused(422, f"robot {i}: the run has robots 0..{robots - 1}")

    def _final_robot(self, i: int) -> dict[str, Any]:
        """Robot ``i`` at the end: its last answer, else what the last frame shows."""
        self._check_robot(i)
        if i in self._robots:
            return {**self._robots[i], "final": True}
        frame = self.frame
        if frame is None:
            raise LiveRefused(409, f"live run {self.id} has ended ({self.status or self.state})")
        robots = int(np.frombuffer(frame, "<u4", 1, 4)[0])
        x, y, yaw = np.frombuffer(frame, "<f4", 3, 12 + 12 * i).tolist()
        goal = (self.meta.get("goals") or [None] * robots)[i]
        return {"id": i, "type": None, "state": STATE_NAMES[frame[12 + 12 * robots + i]],
                "time": self.time, "x": x, "y": y, "yaw": yaw, "v": None, "w": None,
                "vRef": None, "headingRef": None, "goal": goal, "lines": [], "skipped": 0,
                "final": True}

    def command(self, name: str, argument: Any = None) -> dict[str, Any]:
        """Send ``play``, ``pause``, ``step``, ``stop`` or ``speed``; the run's state after.

        Stop answers once the run has ended, or ``stopping`` after :data:`STOP_WAIT`.

        Raises:
            LiveRefused: 409 when the run has ended or not started, 504 when the
                worker does not answer.
        """
        if name == "stop":
            return self._stop()
        answer = self._ask(name, argument)
        self._take_answer(answer)
        self._notify()
        return self.as_dict()

    def _take_answer(self, answer: dict[str, Any]) -> None:
        with self._lock:
            if self.state not in (*ENDED, "stopping"):
                self.state = {"playing": "running", "paused": "paused"}.get(answer["state"],
                                                                            self.state)
                self.speed = answer["speed"]
            if answer["step"] > self.step:
                self.step, self.time = answer["step"], answer["time"]

    def _stop(self) -> dict[str, Any]:
        with self._lock:
            if self.state == "stopping":  # a second Stop: the first one's answer
                ask = False
            else:
                self._check_going()
                self.state, ask = "stopping", True
        self._notify()
        if ask:
            try:
                self._take_answer(self._ask("stop", None))
            except LiveRefused as refusal:
                if refusal.status != 409:  # (409: it ended meanwhile, as asked)
                    raise
            threading.Thread(target=self._end_if_stuck, daemon=True).start()
        self._ended.wait(STOP_WAIT + 1.0)  # the end comes on the stream, after the answer
        self._notify()
        return self.as_dict()

    def _ask(self, name: str, argument: Any) -> dict[str, Any]:
        """One command and the worker's answer (refusals raised)."""
        with self._control_lock:
            if name != "stop":
                self._check_going()
            try:
                self._control.send((name, argument))
                if not self._control.poll(COMMAND_TIMEOUT):
                    raise LiveRefused(504, f"live run {self.id}: no answer to {name} in "
                                           f"{COMMAND_TIMEOUT:g} s (a step that does not "
                                           "return?)")
                answer = self._control.recv()
            except (EOFError, OSError, BrokenPipeError):
                raise LiveRefused(409, f"live run {self.id} has ended") from None
        if answer.get("error"):
            raise LiveRefused(422, answer["error"])
        return answer

    def edit(self, edit: dict[str, Any]) -> dict[str, Any]:
        """Apply ``edit`` at the next step boundary; the applied edit (with step and time).

        Raises:
            LiveRefused: 422 with the worker's one line when the edit is refused, 409
                when the run has ended, 504 when no step boundary came in time.
        """
        with self._edit_lock:
            self._check_going()
            try:
                self._edits.send(edit)
                if not self._edits.poll(EDIT_TIMEOUT):
                    raise LiveRefused(504, f"live run {self.id}: the edit was not applied in "
                                           f"{EDIT_TIMEOUT:g} s (a step that does not return?)")
                verdict, detail = self._edits.recv()
            except (EOFError, OSError, BrokenPipeError):
                raise LiveRefused(409, f"live run {self.id} has ended") from None
        if verdict != "ok":
            raise LiveRefused(422, detail)
        return detail

    def _check_going(self) -> None:
        if self.state == "starting":
            raise LiveRefused(409, f"live run {self.id} is still starting")
        if self.state == "stopping":
            raise LiveRefused(409, f"live run {self.id} is stopping")
        if self.state in ENDED:
            raise LiveRefused(409, f"live run {self.id} has ended ({self.status or self.state})")

    def _end_if_stuck(self) -> None:
        """After Stop: end the worker if the run has not ended within :data:`STOP_GRACE`."""
        self.process.join(STOP_GRACE)
        if self.process.is_alive() and self.state not in ENDED:
            with self._lock:
                self.state = "error"
                self.error = (f"stopped: step {self.step + 1} did not return within "
                              f"{STOP_GRACE:g} s of Stop; the worker was ended (the run folder "
                              "keeps what was recorded, without summary.json)")
            self.process.kill()

    def close(self, timeout: float = 5.0) -> None:
        """Stop the run (its folder complete) and end its worker (the server is leaving)."""
        if self.process.is_alive() and self.state not in ENDED:
            with contextlib.suppress(LiveRefused):
                self.command("stop")
            self.process.join(timeout)
        if self.process.is_alive():
            self.process.kill()

    def as_dict(self) -> dict[str, Any]:
        """The JSON form the API returns (``run`` relative to the workspace by the caller)."""
        return {"id": self.id, "state": self.state, "step": self.step, "time": self.time,
                "speed": self.speed if self.speed != float("inf") else "fastest",
                "run": self.run, "status": self.status, "error": self.error,
                "watchers": self.watchers, "started": self.started, **self.label}


class LiveRuns:
    """The server's live runs, by id."""

    def __init__(self) -> None:
        self._runs: dict[int, LiveRun] = {}
        self._ids = itertools.count(1)
        self._lock = threading.Lock()

    def start(self, request: dict[str, Any], label: dict[str, Any]) -> LiveRun:
        """Start a worker for ``request`` (see ``worker_main``); ``label`` is reported as is.

        Raises:
            LiveRefused: 429 when :data:`MAX_RUNNING` runs are going already.
        """
        with self._lock:
            going = [r for r in self._runs.values() if r.state not in ENDED]
            if len(going) >= MAX_RUNNING:
                raise LiveRefused(429, f"{len(going)} live runs are going already (at most "
                                       f"{MAX_RUNNING}); stop one first")
            run = LiveRun(next(self._ids), request, label)
            self._runs[run.id] = run
        return run

    def get(self, run_id: int) -> LiveRun:
        """The live run ``run_id``.

        Raises:
            LiveRefused: 404 when there is none.
        """
        run = self._runs.get(run_id)
        if run is None:
            raise LiveRefused(404, f"no live run {run_id}")
        return run

    def all(self) -> list[LiveRun]:
        """Every live run of this server, newest first."""
        return sorted(self._runs.values(), key=lambda r: -r.id)

    def close(self) -> None:
        """Stop every live run (the server is shutting down)."""
        for run in list(self._runs.values()):
            run.close()
