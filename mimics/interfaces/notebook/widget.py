"""LiveWidget: the anywidget of ``mimics.show`` (see :mod:`mimics.interfaces.notebook.live`).

The page side is ``widget.js`` beside this file: it shows the frames (PNG
bytes) and sends the buttons' commands; this side steps the simulation with a
:class:`~mimics.interfaces.stepper.SimulationStepper`, records it in memory
and draws the frames with a :class:`~mimics.interfaces.notebook.frames.FrameDrawer`.
"""

from __future__ import annotations

import math
import threading
from pathlib import Path
from typing import Any

import anywidget
import traitlets

from mimics.interfaces.notebook.frames import FrameDrawer
from mimics.interfaces.stepper import SimulationStepper
from mimics.records.memory import MemoryRecorder, MemoryRun
from mimics.world.errors import MimicsError

_COMMANDS = ("play", "pause", "step", "stop")


class LiveWidget(anywidget.AnyWidget):  # type: ignore[misc]
    """A simulation shown while it runs, with its controls (see :func:`show`).

    Python holds the same controls as the page: :meth:`play`, :meth:`pause`,
    :meth:`step`, :meth:`stop`, ``speed`` (simulated seconds per second, 0: as
    fast as possible), and :meth:`wait` for the end.
    """

    _esm = Path(__file__).with_name("widget.js").read_text()
    frame = traitlets.Bytes(b"").tag(sync=True)
    frames = traitlets.Int(0).tag(sync=True)
    time = traitlets.Float(0.0).tag(sync=True)
    state = traitlets.Unicode("paused").tag(sync=True)
    status = traitlets.Unicode("running").tag(sync=True)
    speed = traitlets.Float(1.0).tag(sync=True)
    title = traitlets.Unicode("").tag(sync=True)

    def __init__(self, sim: Any, *, speed: float = 1.0, fps: float = 10.0,
                 width_px: int = 640, trail: float = 5.0, beams_of: int | None = None,
                 autoplay: bool = True) -> None:
        super().__init__(speed=float(speed) if math.isfinite(speed) else 0.0,
                         title=f"{sim.scenario.name} / {sim.controller.name} / seed {sim.seed}")
        self.sim = sim
        self.recorder = MemoryRecorder()
        self.drawer = FrameDrawer(width_px, trail, beams_of)
        sim.observers.extend([self.recorder, self.drawer])
        self._sending = threading.Lock()
        self.stepper = SimulationStepper(sim, self._on_frame, fps=fps,
                                         speed=self.speed or math.inf)
        self.on_msg(self._on_message)
        self.observe(self._on_speed, names="speed")
        if autoplay:
            self.play()

    # -- controls ------------------------------------------------------------------

    def play(self) -> None:
        """Run on at the chosen speed."""
        self.stepper.play()
        self._show_state()

    def pause(self) -> None:
        """Pause after the current step."""
        self.stepper.pause()
        self._show_state()

    def step(self) -> None:
        """Pause and advance one step."""
        self.stepper.step()
        self._show_state()

    def stop(self) -> None:
        """End the run at the next step (status ``"stopped"``)."""
        self.stepper.stop()

    def wait(self, timeout: float | None = None) -> Any:
        """Wait for the run to end (playing it if paused); returns its RunView."""
        if self.stepper.state == "paused":
            self.play()
        if not self.stepper.wait_ended(timeout):
            raise MimicsError(f"show: the run had not ended after {timeout} s")
        return self.run

    @property
    def run(self) -> Any:
        """The finished run (a RunView, recorded in memory).

        Raises:
            MimicsError: while the run goes on.
        """
        from mimics.interfaces.notebook.run import RunView

        if self.sim.status == "running" or self.recorder.trajectory is None:
            raise MimicsError("show: the run has not ended yet (press Play or Stop, or call "
                              ".wait())")
        result = self.sim.result()
        return RunView(MemoryRun(self.recorder, result), result)

    def close(self) -> None:
        """Close the widget and leave the stepping thread."""
        self.stepper.close()
        super().close()

    # -- the kernel side of the page -------------------------------------------------

    def _on_message(self, widget: Any, content: Any, buffers: Any) -> None:
        command = content.get("command") if isinstance(content, dict) else None
        if command in _COMMANDS:
            getattr(self, command)()

    def _on_speed(self, change: dict[str, Any]) -> None:
        value = float(change["new"])
        self.stepper.set_speed(value if value > 0 else math.inf)

    def _show_state(self) -> None:
        with self._sending:
            self.state = ("ended" if self.sim.status != "running" or self.stepper.state == "ended"
                          else self.stepper.state)

    def _on_frame(self, sim: Any) -> None:
        """From the stepper's thread: draw and send one frame with its time and state."""
        png = self.drawer.png(sim)
        with self._sending, self.hold_sync():
            self.frame = png
            self.frames += 1
            # a sum of steps (0.1 + 0.2 = 0.30000000000000004): shown to the nanosecond
            self.time = round(float(sim.state.time), 9)
            self.status = sim.status
            self.state = "ended" if sim.status != "running" else self.stepper.state
