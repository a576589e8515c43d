"""A robot type's closed-loop responses as a figure: speed step, stop and 90 degree turn.

The responses are the engine's own (:func:`mimics.engine.responses.standard_responses`
steps the simulation's PID loops and dynamics), drawn in the style of the
other static plots (:mod:`mimics.interfaces.plots`). ``mimics robot show``
writes this figure; the docs' ``docs/images/robot_<type>.png`` are made by it.

>>> from mimics.interfaces.robot_plots import TOLERANCES
>>> TOLERANCES["speed"], round(TOLERANCES["heading"], 4)
(0.02, 0.0349)
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.axes import Axes

from mimics.engine.responses import Response, overshoot, settling_time, standard_responses
from mimics.interfaces.plots import _new_figure, _save
from mimics.world.robot_types import RobotType

#: Settling bands: 2% of a speed step, 2 degrees of a turn.
TOLERANCES = {"speed": 0.02, "heading": math.radians(2)}
REFERENCE_COLOR, RESPONSE_COLOR, ACTUATION_COLOR = "#555555", "#1f77b4", "#ff7f0e"


def response_metrics(robot_type: RobotType, dt: float = 0.1) -> dict[str, float]:
    """Settling times (s) and overshoots (fraction) of the three standard responses."""
    figures = standard_responses(robot_type, dt=dt)
    r = figures.speed_ref
    return {
        "speed_step": r,
        "step_settling": settling_time(figures.speed_step.speed, figures.speed_step.time, r,
                                       TOLERANCES["speed"] * r),
        "step_overshoot": overshoot(figures.speed_step.speed, 0.0, r),
        "stop_settling": settling_time(figures.stop.speed, figures.stop.time, 0.0,
                                       TOLERANCES["speed"] * r),
        "stop_overshoot": overshoot(figures.stop.speed, r, 0.0),
        "turn_settling": settling_time(figures.turn.heading, figures.turn.time, math.pi / 2,
                                       TOLERANCES["heading"]),
        "turn_overshoot": overshoot(figures.turn.heading, 0.0, math.pi / 2),
    }


def _panel(ax: Axes, response: Response, values: np.ndarray, start: float, target: float,
           band: float, title: str, unit: str) -> None:
    time = response.time
    ax.axhspan(target - band, target + band, color="#2ca02c", alpha=0.15, lw=0,
               label="settling band")
    ax.step([-0.2, 0.0, time[-1]], [start, target, target], where="post",
            color=REFERENCE_COLOR, ls="--", lw=1.0, label="reference")
    ax.plot(time, values, color=RESPONSE_COLOR, marker=".", ms=3, lw=1.2, label="response")
    settled = settling_time(values, time, target, band)
    over = overshoot(values, start, target)
    if math.isfinite(settled):
        ax.axvline(settled, color="#2ca02c", lw=0.8, ls=":")
    ax.set_title(f"{title}: settles in {settled:.1f} s, overshoot {100 * over:.1f}%",
                 fontsize=9)
    ax.set_xlabel("time (s)")
    ax.set_ylabel(unit)
    twin = ax.twinx()
    column = 0 if unit.startswith("speed") else 1
    twin.step(time[:-1], response.actuation[:-1, column], where="post", color=ACTUATION_COLOR,
              lw=0.8, alpha=0.7)
    twin.set_ylim(-1.1, 1.1)
    twin.set_ylabel("actuation u", color=ACTUATION_COLOR, fontsize=8)
    twin.tick_params(axis="y", labelsize=7, colors=ACTUATION_COLOR)


def plot_robot_responses(robot_type: RobotType, out: str | Path, *, dt: float = 0.1,
                         width_px: int = 1500, height_px: int = 450) -> Path:
    """Speed step, stop and 90 degree turn of a robot type, side by side, as a PNG.

    Args:
        robot_type: The type to show (its plant and gains).
        out: The PNG to write.
        dt: Control period (s).
        width_px: Image width in pixels.
        height_px: Image height in pixels.

    Returns:
        The path written.

    Raises:
        MimicsError: ``out`` cannot be written, or a size below 100 pixels.

    Example:
        >>> from mimics.world.robot_types import PIONEER_3AT
        >>> plot_robot_responses(PIONEER_3AT, "robot.png")  # doctest: +SKIP
    """
    figures = standard_responses(robot_type, dt=dt)
    r = figures.speed_ref
    fig = _new_figure(width_px, height_px)
    axes = fig.subplots(1, 3)
    _panel(axes[0], figures.speed_step, figures.speed_step.speed, 0.0, r,
           TOLERANCES["speed"] * r, f"speed step 0 -> {r:.3g} m/s", "speed (m/s)")
    _panel(axes[1], figures.stop, figures.stop.speed, r, 0.0, TOLERANCES["speed"] * r,
           f"stop from {r:.3g} m/s", "speed (m/s)")
    _panel(axes[2], figures.turn, np.degrees(figures.turn.heading), 0.0, 90.0,
           math.degrees(TOLERANCES["heading"]), "heading step 90 deg", "heading (deg)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=3, fontsize=8, frameon=False)
    fig.suptitle(f"{robot_type.name}: closed-loop responses at dt = {dt:g} s "
                 "(orange: actuation)", fontsize=10)
    return _save(fig, Path(out))
