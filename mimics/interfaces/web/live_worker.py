"""The worker process of a live run: prepare, record, step on command, stream frames.

A live run never steps in the server's process: :func:`worker_main` runs in a
process of its own (``multiprocessing``'s spawn start method), so a slow or
stuck algorithm cannot stall the workbench. It prepares the simulation through
:func:`mimics.records.runner.prepare`, as ``mimics run`` does, records it into a new
folder (:func:`mimics.records.naming.new_run_folder`: never one taken) with a
:class:`~mimics.records.recorder.RunRecorder`, as ``run_to_folder`` does, and
holds a :class:`~mimics.interfaces.stepper.SimulationStepper` for Play, Pause,
Step, Stop, speed and edits.

It talks to the server over three pipes:

* ``control``: the server sends ``(command, argument)``, the worker answers each
  with a dict (``play``, ``pause``, ``step``, ``stop``, ``speed``, ``robot``);
* ``edits``: the server sends an edit dict, the worker answers
  ``("ok", applied)`` or ``("refused", one line)``; edits have a pipe and a thread
  of their own because one waits for the next step boundary;
* ``stream``: the worker sends ``("ready", info)`` or ``("failed", one line)``
  once, then ``("frame", step, time, body)`` (``body`` in the layout of
  :mod:`mimics.interfaces.web.live_frames`), ``("meta", dict)`` whenever the walls
  or goals change, ``("moved", robot, step)`` when an edit moved a robot (the page
  breaks its trail there), and ``("end", info)`` last.
"""

from __future__ import annotations

import contextlib
import math
import signal
import threading
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

import numpy as np

from mimics.interfaces.render import STATUS_COLORS, beam_segments
from mimics.interfaces.web.live_frames import STATE_NAMES, encode_frames, frame_states
from mimics.world.errors import MimicsError
from mimics.world.map_files import map_to_dict

#: Seconds between checks of the stepper's state while no command arrives.
POLL = 0.05
#: Beams sent for every robot at once: each robot's are thinned to fit (as the replay's).
ALL_BEAMS = 60_000
#: Seconds a beams request waits for a step boundary before it is refused.
BEAMS_WAIT = 5.0
#: Seconds Stop waits for the run's end before it answers (the page then reads "stopping").
STOP_WAIT = 5.0


def worker_main(request: dict[str, Any], control: Connection, edits: Connection,
                stream: Connection) -> None:
    """The live run's process: see the module docstring. ``request`` holds ``scenario``
    (a built-in name or a real path), ``algorithm`` (a built-in name or a real path),
    ``seed``, ``time``, ``params``, ``policy``, ``wall_limit``, ``speed`` (``math.inf``: as
    fast as possible), ``fps``, ``paused`` and ``runs`` (the folder the run folder is made
    in)."""
    from mimics.records.naming import new_run_folder
    from mimics.records.recorder import RunRecorder
    from mimics.records.runner import prepare

    # Ctrl-C in the terminal of `mimics ui` reaches the whole process group: the server,
    # shutting down, stops each live run so that its folder ends complete
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        sim = prepare(request["scenario"], request["algorithm"], seed=request["seed"],
                      time=request["time"], wall_limit=request["wall_limit"],
                      params=request.get("params"), policy=request.get("policy", "abort"))
        folder = new_run_folder(request["runs"], sim.scenario.name, sim.controller.name,
                                request["seed"])
        recorder = RunRecorder(folder)
        sim.observers.append(recorder)
    except MimicsError as exc:
        stream.send(("failed", str(exc)))
        return
    except Exception as exc:  # a bug: one line for the page, not a silent worker
        stream.send(("failed", f"{type(exc).__name__}: {exc}"))
        return
    LiveWorker(sim, recorder, folder, stream, speed=request["speed"],
               fps=request["fps"], paused=request["paused"]).serve(control, edits)


class LiveEnd:
    """The first observer of a live run: at its end, before the recorder writes it, an end
    a re-run would not reach by itself (Stop, the wall limit) joins the scenario's edits
    (``Simulation.record_end``), and the summary gets ``paced_wall_time``: the run's wall
    seconds with its pacing and pauses, beside ``wall_time``, the engine's own."""

    def __init__(self, recorder: Any) -> None:
        self.recorder = recorder

    def on_end(self, sim: Any, result: Any) -> None:
        sim.record_end()
        self.recorder.extra["paced_wall_time"] = sim.wall_time + sim.waited


class LiveWorker:
    """A prepared simulation, its recorder and its stepper, driven from the pipes.

    Args:
        sim: the simulation (not started), with ``recorder`` among its observers.
        recorder: the run's recorder (closed here if the stepper's thread raises).
        folder: the run folder.
        stream: the pipe frames, meta and the end go to.
        speed: simulated seconds per wall second (``math.inf``: as fast as possible).
        fps: frames per wall second at most while playing.
        paused: start paused (else playing).
    """

    def __init__(self, sim: Any, recorder: Any, folder: Path, stream: Connection, *,
                 speed: float, fps: float, paused: bool) -> None:
        from mimics.interfaces.stepper import SimulationStepper

        self.sim = sim
        self.recorder = recorder
        self.folder = folder
        self.stream = stream
        self._send_lock = threading.Lock()
        self._sent_goals: np.ndarray | None = None
        self._sent_walls: Any = None
        self._last_step = -1
        self._flush_next_step = False  # Pause asked: the step in flight is sent when done
        sim.observers.insert(0, LiveEnd(recorder))  # before the recorder's on_end
        sim.observers.append(self)  # on_step: the step in flight at a Pause is sent
        self.stepper = SimulationStepper(sim, self.on_frame, speed=speed, fps=fps)
        self.send("ready", {"run": str(folder), "meta": self.meta(),
                            "speed": self.stepper.speed})
        if not paused:
            self.stepper.play()

    # -- what is sent ---------------------------------------------------------------

    def send(self, *message: Any) -> None:
        """One message on the stream (from any thread)."""
        with self._send_lock, contextlib.suppress(BrokenPipeError, OSError):
            self.stream.send(message)

    def meta(self) -> dict[str, Any]:
        """What the page draws besides the frames: map, robot sizes, goals, colours."""
        sim = self.sim
        scenario = sim.scenario
        lengths = np.array([t.length for t in scenario.types])[scenario.type_index]
        widths = np.array([t.width for t in scenario.types])[scenario.type_index]
        goals = sim.state.goal
        self._sent_goals = goals.copy()
        self._sent_walls = self._walls_key()
        return {"title": f"{scenario.name} / {sim.controller.name} / seed {sim.seed}",
                "robots": int(sim.state.n), "map": map_to_dict(sim.world_map),
                "half_length": (lengths / 2).tolist(), "half_width": (widths / 2).tolist(),
                "goals": [None if math.isnan(g[0]) else [float(g[0]), float(g[1])]
                          for g in goals.tolist()],
                "dt": float(scenario.settings.dt), "colors": STATUS_COLORS}

    def _walls_key(self) -> tuple[int, int]:
        segments = self.sim.world_map.segments  # the walls as edited so far
        return id(segments), len(segments)

    def frame(self) -> tuple[int, float, bytes]:
        """The simulation's current step as a frame body."""
        state = self.sim.state
        states = frame_states(state.status, state.in_livelock)
        body = encode_frames(np.array([state.time]), state.pose[None], states[None])
        return int(state.step), float(state.time), body

    def send_frame(self, frame: tuple[int, float, bytes]) -> None:
        """A frame, after the meta when walls or goals changed since the last."""
        goals = self.sim.state.goal
        if (self._sent_goals is None or goals.shape != self._sent_goals.shape
                or not np.array_equal(goals, self._sent_goals, equal_nan=True)
                or self._walls_key() != self._sent_walls):
            self.send("meta", self.meta())
        self._last_step = frame[0]
        self.send("frame", *frame)

    def on_frame(self, sim: Any) -> None:
        """The stepper's frame callback (its thread; the simulation holds still)."""
        self.send_frame(self.frame())

    def on_step(self, sim: Any) -> None:
        """Observer: after a Pause, the step that was in flight is sent (the stepper
        draws only ``fps`` frames a second, so the page would keep an older one)."""
        if self._flush_next_step:
            self._flush_next_step = False
            self.send_frame(self.frame())

    # -- commands ------------------------------------------------------------------

    def status(self) -> dict[str, Any]:
        """The stepper's state, step, time and speed."""
        state = self.sim.state
        return {"state": self.stepper.state, "step": int(state.step),
                "time": float(state.time), "speed": self.stepper.speed}

    def command(self, name: str, argument: Any) -> dict[str, Any]:
        """Run one control command; its answer (``error`` set when refused)."""
        stepper = self.stepper
        try:
            if name == "play":
                stepper.play()
            elif name == "pause":
                self._flush_next_step = True
                stepper.pause()
                self._send_quiet_frame()
            elif name == "step":
                stepper.step()
                stepper.wait_paused()
            elif name == "stop":  # answered once the run has ended (or STOP_WAIT passed)
                stepper.stop()
                with contextlib.suppress(BaseException):  # a raise is finish()'s to report
                    stepper.wait_ended(STOP_WAIT)
            elif name == "speed":
                stepper.set_speed(float(argument))
            elif name == "robot":
                return {**self.status(), "robot": self.robot(int(argument))}
            elif name == "beams":
                return {**self.status(), "beams": self.beams_now(argument)}
            else:
                return {**self.status(), "error": f"unknown command {name!r}"}
        except MimicsError as exc:
            return {**self.status(), "error": str(exc)}
        return self.status()

    def robot(self, i: int) -> dict[str, Any]:
        """Robot ``i`` now, for the inspector: id, type, state, pose, v, w, references,
        goal, and its events so far as log lines (its per-robot log is written at the end).

        Raises:
            MimicsError: when there is no robot ``i``.
        """
        sim = self.sim
        state = sim.state
        if not 0 <= i < state.n:
            raise MimicsError(f"robot {i}: the run has robots 0..{state.n - 1}")
        code = int(frame_states(state.status[i:i + 1], state.in_livelock[i:i + 1])[0])
        goal = state.goal[i]
        events = [e for e in list(sim.events) if e.robot == i]
        return {"id": i, "type": sim.scenario.types[sim.scenario.type_index[i]].name,
                "state": STATE_NAMES[code], "time": float(state.time),
                "x": float(state.pose[i, 0]), "y": float(state.pose[i, 1]),
                "yaw": float(state.pose[i, 2]), "v": float(state.velocity[i, 0]),
                "w": float(state.velocity[i, 1]), "vRef": float(state.reference[i, 0]),
                "headingRef": float(state.reference[i, 1]),
                "goal": None if math.isnan(goal[0]) else [float(goal[0]), float(goal[1])],
                "lines": [f"{e.time:.2f} s  {e.kind}: {e.detail}" for e in events[-2000:]],
                "skipped": max(0, len(events) - 2000)}

    def beams_now(self, argument: Any) -> dict[str, Any]:
        """``beams`` at the next step boundary (a short wait: a Stop must not queue behind a
        long step), or at once once the run has ended (nothing steps any more)."""
        robot = None if argument == "all" else int(argument)
        if self.stepper.state != "ended":
            try:
                return self.stepper.between_steps(lambda sim: self.beams(robot),
                                                  timeout=BEAMS_WAIT)
            except MimicsError:
                if self.stepper.state != "ended":
                    raise
        with contextlib.suppress(BaseException):  # a raise is finish()'s to report
            self.stepper.wait_ended(BEAMS_WAIT)
        return self.beams(robot)

    def beams(self, robot: int | None) -> dict[str, Any]:
        """The beams of robot ``robot``'s scan now (None: every active robot's), as the
        engine sensed them for the next step (the ranges the algorithm reads, noise
        included), from each robot's pose: ``segments`` ``[x0, y0, x1, y1]``, ``every``
        (each robot's every k-th beam, so that at most :data:`ALL_BEAMS` come), ``step``,
        ``time``. Call it in the stepper's thread (``between_steps``): reading the scan
        traces its rays, which must not race a step.

        Raises:
            MimicsError: when there is no robot ``robot``.
        """
        sim = self.sim
        state, types = sim.state, sim.types
        if robot is not None and not 0 <= robot < state.n:
            raise MimicsError(f"robot {robot}: the run has robots 0..{state.n - 1}")
        scanning = np.logical_not(state.status) & (types.beam_count > 0)
        if robot is not None:
            ids = np.array([robot]) if scanning[robot] else np.zeros(0, dtype=np.int64)
        else:
            ids = np.flatnonzero(scanning)
        every = max(1, math.ceil(int(types.beam_count[ids].sum()) / ALL_BEAMS))
        flat = np.zeros((0, 4))
        if ids.size:
            ranges = state.scan  # the first read traces the rays of the last sensing
            flat = np.concatenate([beam_segments(state.pose[r, :2], float(state.pose[r, 2]),
                                                 types.beam_offsets[r, ::every],
                                                 ranges[r, ::every])
                                   for r in ids.tolist()]).reshape(-1, 4)
        return {"segments": np.round(flat, 4).tolist(), "every": every,
                "step": int(state.step), "time": float(state.time)}

    def _send_quiet_frame(self) -> None:
        """After Pause: the last step taken, unless the step in flight sends its own."""
        step = int(self.sim.state.step)
        if step > self._last_step and self.stepper.state == "paused":
            self.send_frame(self.frame())

    def edit_loop(self, edits: Connection) -> None:
        """Apply edits in order (each waits for a step boundary); answer each."""
        while True:
            try:
                edit = edits.recv()
            except (EOFError, OSError):
                return
            try:
                applied = self.stepper.edit(edit)
            except MimicsError as exc:
                answer: tuple[str, Any] = ("refused", str(exc).splitlines()[0])
            except Exception as exc:  # a bug: one line for the page
                answer = ("refused", f"{type(exc).__name__}: {exc}")
            else:
                answer = ("ok", applied)
                if applied["kind"] == "move_robot":  # the page breaks its trail there
                    self.send("moved", applied["robot"], applied["step"])
                if self.stepper.state == "paused":  # no frame would show it until Play
                    self.send_frame(self.frame())
            with contextlib.suppress(BrokenPipeError, OSError):
                edits.send(answer)

    def serve(self, control: Connection, edits: Connection) -> None:
        """Answer commands until the run ends, then send ``end``."""
        threading.Thread(target=self.edit_loop, args=(edits,), name="mimics-live-edits",
                         daemon=True).start()
        wall_limit = self.sim.wall_limit
        while self.stepper.state != "ended":
            try:
                if not control.poll(POLL):
                    # the wall limit counts pauses, but only a step checks it: a run paused
                    # past it ends here, as if it had stepped on to its limit
                    if (wall_limit is not None and self.stepper.state == "paused"
                            and self.sim.elapsed() >= wall_limit):
                        self.stepper.stop("wall_limit")
                    continue
                name, argument = control.recv()
            except (EOFError, OSError):  # the server went away: end the run, keep its folder
                self.stepper.stop()
                break
            answer = self.command(name, argument)
            with contextlib.suppress(BrokenPipeError, OSError):
                control.send(answer)
        self.finish()

    def finish(self) -> None:
        """Wait for the run's end and send ``end`` (status, error, step, time)."""
        sim = self.sim
        error = ""
        try:
            self.stepper.wait_ended()
        except BaseException as exc:  # the stepper's thread raised: keep what was recorded
            error = f"{type(exc).__name__}: {exc}" if not isinstance(exc, MimicsError) \
                else str(exc)
            self.close_in_error(error)
        error = error or sim.error or ""
        self.send("end", {"status": sim.status, "error": error, "step": int(sim.state.step),
                          "time": float(sim.state.time)})

    def close_in_error(self, error: str) -> None:
        """End a run whose stepper raised as a run that ended in error: its folder gets
        scenario.toml with the edits made so far and summary.json (status ``error``),
        as a run whose algorithm raised does, so it still re-runs from its folder. If
        even that fails, what was recorded is kept (without summary.json)."""
        sim = self.sim
        if sim.status == "running":
            sim.status, sim.error = "error", error
        try:
            if not self.recorder.finished:
                self.recorder.on_end(sim, sim.result())
        except Exception:
            with contextlib.suppress(Exception):
                self.recorder.close()
