"""The interactive replay window (Matplotlib): play/pause, a time slider, a speed slider."""

from __future__ import annotations

from typing import Any

import numpy as np

from mimics.interfaces.replay.drawing import Replayer
from mimics.interfaces.replay.frames import _EPS, ReplayData


class ReplayWindow:
    """An interactive replay: play/pause, a time slider and a speed slider.

    Keys: space plays or pauses, left/right step one frame back or forward.

    Args:
        data: the run's dense arrays.
        fps: frames per second while playing.
        speed: initial simulated seconds per second (1/4 to 64, powers of 2).
        robot_beams: robot whose beams are drawn, or None.
        trail: seconds of trail behind each robot.
        figure: a figure to draw into (default: a new pyplot window).
    """

    _CONTROLS_PX = 64

    def __init__(self, data: ReplayData, *, fps: float = 10.0, speed: float = 1.0,
                 robot_beams: int | None = None, trail: float = 5.0,
                 figure: Any = None) -> None:
        from matplotlib.widgets import Button, Slider

        if figure is None:
            import matplotlib.pyplot as plt

            figure = plt.figure(num=f"mimics replay: {data.title}")
        self.data = data
        self.fps = fps
        self.replayer = Replayer.create(data, extra_bottom_px=self._CONTROLS_PX, figure=figure,
                                        trail=trail, robot_beams=robot_beams)
        self.figure = figure
        self.time = 0.0
        self.playing = False
        height = figure.bbox.height
        row = 10 / height
        tall = 22 / height
        self._play_ax = figure.add_axes((0.01, row + tall + 6 / height, 0.1, tall))
        self.play_button = Button(self._play_ax, "Play")
        self.play_button.on_clicked(lambda _event: self.toggle())
        self.time_slider = Slider(figure.add_axes((0.2, row + tall + 6 / height, 0.68, tall)),
                                  "time (s)", 0.0, max(data.duration, 1e-9), valinit=0.0)
        self.time_slider.on_changed(self._on_time)
        exponent = float(np.clip(np.round(np.log2(speed)), -2, 6))
        self.speed_slider = Slider(figure.add_axes((0.2, row, 0.3, tall)), "speed", -2.0, 6.0,
                                   valinit=exponent, valstep=1.0)
        self.speed_slider.valtext.set_text(f"x{2 ** exponent:g}")
        self.speed_slider.on_changed(
            lambda value: self.speed_slider.valtext.set_text(f"x{2 ** value:g}"))
        self.timer = figure.canvas.new_timer(interval=max(1, int(1000 / fps)))
        self.timer.add_callback(self.tick)
        figure.canvas.mpl_connect("key_press_event", self._on_key)
        self.replayer.show_at(0.0)

    @property
    def speed(self) -> float:
        """Simulated seconds per second of playback."""
        return float(2.0 ** self.speed_slider.val)

    def seek(self, t: float) -> None:
        """Show simulated time ``t`` (clamped to the run) and move the slider there."""
        self.time = float(np.clip(t, 0.0, self.data.duration))
        self.time_slider.set_val(self.time)  # calls _on_time, which draws

    def _on_time(self, value: float) -> None:
        self.time = float(value)
        self.replayer.show_at(self.time)
        self.figure.canvas.draw_idle()

    def toggle(self) -> None:
        """Play or pause (playing from the end starts again at 0)."""
        self.playing = not self.playing
        self.play_button.label.set_text("Pause" if self.playing else "Play")
        if self.playing:
            if self.time >= self.data.duration - _EPS:
                self.seek(0.0)
            self.timer.start()
        else:
            self.timer.stop()
        self.figure.canvas.draw_idle()

    def tick(self) -> None:
        """Advance one frame while playing; pause at the end."""
        if not self.playing:
            return
        self.seek(self.time + self.speed / self.fps)
        if self.time >= self.data.duration - _EPS:
            self.toggle()

    def _on_key(self, event: Any) -> None:
        if event.key == " ":
            self.toggle()
        elif event.key in ("left", "right"):
            step = self.speed / self.fps
            self.seek(self.time + (step if event.key == "right" else -step))

    def show(self) -> None:
        """Open the window and block until it is closed."""
        import matplotlib.pyplot as plt

        plt.show()
