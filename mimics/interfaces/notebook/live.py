"""``mimics.show``: a simulation drawn in a notebook cell while it runs.

The cell shows an `anywidget <https://anywidget.dev>`_ widget (JupyterLab,
Notebook 7, VS Code, Colab): Play, Pause, Step, Stop and a speed choice. The
simulation steps in a background thread (:class:`~mimics.interfaces.stepper.SimulationStepper`),
so the kernel stays free: the buttons' messages are handled between cells,
and other cells can run meanwhile. Frames are drawn by the replay's and the
live view's renderer (:class:`~mimics.interfaces.render.WorldRenderer`: the
same walls, robot bodies, state colours, trails and legend) and sent to the
page as PNG bytes, at most ``fps`` a second. The run is recorded in memory, as
by ``mimics.simulate``: once it has ended, ``view.run`` is its
:class:`~mimics.interfaces.notebook.run.RunView`.

Where widgets cannot be shown (no anywidget installed, or not in a Jupyter
kernel) ``show`` runs the simulation to its end and returns its
``.animate()`` instead, saying so in one line.
"""

from __future__ import annotations

import importlib.util
import math
import sys
from typing import Any

from mimics.interfaces.notebook.html import in_kernel

#: Simulated seconds per wall second at most, short of math.inf (a finite 1e300 is a typo).
MAX_SPEED = 1e15


def widgets_available() -> bool:
    """True where a widget can be shown: anywidget is installed and a kernel runs."""
    return importlib.util.find_spec("anywidget") is not None and in_kernel()


def show(scenario: Any, algorithm: Any, *, robots: int | None = None,
         time: float | None = None, seed: int = 0, params: dict[str, Any] | None = None,
         policy: str = "abort", speed: float = 1.0, fps: float = 10.0, width_px: int = 640,
         trail: float = 5.0, beams_of: int | None = None, autoplay: bool = True,
         widget: bool | None = None) -> Any:
    """A live view of a new simulation in the cell (a
    ``mimics.interfaces.notebook.widget.LiveWidget``).

    Args:
        scenario: a built-in name, a ``.py``/``.toml`` file or a Scenario.
        algorithm: a built-in name, a ``.py`` file, or a module/function/class.
        robots: as for ``mimics.simulate``.
        time: as for ``mimics.simulate``.
        seed: as for ``mimics.simulate``.
        params: as for ``mimics.simulate``.
        policy: as for ``mimics.simulate``.
        speed: simulated seconds per wall second (``math.inf`` or 0: as fast as possible).
        fps: frames sent to the page per second at most.
        width_px: pixels of the longer side of the map.
        trail: seconds of trail behind each robot.
        beams_of: a robot whose laser beams are drawn.
        autoplay: start playing at once (else wait for Play or Step).
        widget: None: a widget where one can be shown, else the run's ``.animate()``;
            False: always the animation.

    Raises:
        MimicsError: a bad scenario, algorithm or option (before anything runs).
    """
    from mimics.interfaces.notebook.animation import check_drawing
    from mimics.interfaces.stepper import check_speed
    from mimics.records.runner import prepare
    from mimics.world.errors import MimicsError
    from mimics.world.limits import check_number

    fastest = isinstance(speed, int | float) and not isinstance(speed, bool) and (
        speed == 0 or speed == math.inf)  # both: as fast as possible
    if not fastest:
        check_number("speed", speed, 0.0, MAX_SPEED, "a number of simulated seconds per "
                     "second (or 0 or math.inf: as fast as possible)")
        check_speed(speed)
    check_drawing(width_px=width_px, fps=fps, trail=trail, robot_beams=beams_of)
    for name, flag in (("autoplay", autoplay), ("widget", widget)):
        if not isinstance(flag, bool) and not (name == "widget" and flag is None):
            raise MimicsError(f"show: {name}: expected True or False, got {flag!r}")
    if widget is None:
        widget = widgets_available()
    sim = prepare(scenario, algorithm, robots=robots, time=time, seed=seed, params=params,
                  policy=policy)  # type: ignore[arg-type]
    if not widget:
        from mimics.interfaces.notebook.run import record_run

        print("mimics.show: no widgets here (anywidget and a Jupyter kernel are needed): "
              "running to the end and showing the replay", file=sys.stderr)
        return record_run(sim).animate(fps=fps, width_px=width_px, trail=trail,
                                       robot_beams=beams_of)
    from mimics.interfaces.notebook.widget import LiveWidget

    pace = 0.0 if speed == 0 else speed
    return LiveWidget(sim, speed=pace if pace else math.inf, fps=fps, width_px=width_px,
                      trail=trail, beams_of=beams_of, autoplay=autoplay)
