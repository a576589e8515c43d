"""Command-line front ends of robot types: `mimics robot show TYPE`, `mimics list robots`.

Plain Typer pieces; the main CLI registers them::

    app.add_typer(robot_app, name="robot")
    list_app.command("robots")(list_robots_command)

An unknown type name is one line ``mimics: error: ...`` listing the known
names, exit status 2.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from mimics.interfaces.cli.output import fail, say
from mimics.world.errors import MimicsError
from mimics.world.noise_sources import NOISE_SOURCES
from mimics.world.robot_types import BUILTIN_ROBOT_TYPES, RobotType, builtin_robot_type

robot_app = typer.Typer(help="Robot types: their parameters and closed-loop responses.",
                        no_args_is_help=True, rich_markup_mode=None)


def _parameter_rows(t: RobotType) -> list[tuple[str, str]]:
    ranger = t.ranger
    sp, hp = t.speed_pid, t.heading_pid
    assert sp is not None and hp is not None  # set by RobotType
    if ranger.beams:
        spread = (f"{len(ranger.angles)} beams at "
                  f"{', '.join(f'{math.degrees(a):g}' for a in ranger.angles)} deg"
                  if ranger.angles else
                  f"{ranger.beams} beams over {math.degrees(ranger.fov):g} deg")
        sensor = f"{ranger.name}: {spread}, {ranger.range:g} m, sigma {ranger.sigma:g} m"
    else:
        sensor = "none"
    return [
        ("size (length x width)", f"{t.length:g} x {t.width:g} m"),
        ("top speed kv", f"{t.kv:g} m/s"),
        ("top turn rate kw", f"{t.kw:.4g} rad/s ({math.degrees(t.kw):.4g} deg/s)"),
        ("time constants tau_v, tau_w", f"{t.tau_v:.4g} s, {t.tau_w:.4g} s"),
        ("speed PID kp, ki, kd", f"{sp.kp:.4g}, {sp.ki:.4g}, {sp.kd:.4g}"),
        ("heading PID kp, ki, kd", f"{hp.kp:.4g}, {hp.ki:.4g}, {hp.kd:.4g}"),
        ("ranger", sensor),
        ("positioning sigma (pos, vel, acc)",
         f"{t.positioning.sigma_position:g} m, {t.positioning.sigma_velocity:g} m/s, "
         f"{t.positioning.sigma_acceleration:g} m/s^2"),
        ("odometry sigma (per m, per rad)",
         f"{t.odometry.sigma_translation:g}, {t.odometry.sigma_rotation:g}"),
        ("noise source", NOISE_SOURCES.get(t.name, "the type's own file")),
        ("noise off", 'a scenario setting noise = "off" (or --param noise=off) runs it exact'),
    ]


@robot_app.command("show")
def show_command(
    name: Annotated[str, typer.Argument(metavar="TYPE", help="A built-in robot type "
                                                              "(`mimics list robots`).")],
    out: Annotated[Path | None, typer.Option(help="PNG of the responses "
                                                  "[default: robot_TYPE.png]")] = None,
) -> None:
    """Print a robot type's parameters and plot its speed step, stop and 90 degree turn.

    The responses are the simulation's own PID loops and dynamics at dt = 0.1 s;
    the speed step is half the top speed, or less where that would saturate.
    """
    from mimics.interfaces.robot_plots import plot_robot_responses, response_metrics

    try:
        robot_type = builtin_robot_type(name)
    except MimicsError as exc:
        raise fail(str(exc)) from None
    metrics = response_metrics(robot_type)
    table = Table(title=robot_type.name, show_header=False)
    table.add_column(style="bold")
    table.add_column()
    rows = [
        *_parameter_rows(robot_type),
        (f"speed step to {metrics['speed_step']:.3g} m/s",
         f"settles (2%) in {metrics['step_settling']:.1f} s, overshoot "
         f"{100 * metrics['step_overshoot']:.1f}%"),
        ("stop", f"settles (2%) in {metrics['stop_settling']:.1f} s, overshoot "
                 f"{100 * metrics['stop_overshoot']:.1f}%"),
        ("90 deg turn", f"settles (2 deg) in {metrics['turn_settling']:.1f} s, overshoot "
                        f"{100 * metrics['turn_overshoot']:.1f}%"),
    ]
    for label, value in rows:
        table.add_row(label, value)
    Console(highlight=False).print(table)
    target = out if out is not None else Path(f"robot_{robot_type.name}.png")
    try:
        written = plot_robot_responses(robot_type, target)
    except MimicsError as exc:
        raise fail(str(exc)) from None
    say(f"wrote {written}")


def list_robots_command() -> None:
    """Built-in robot types, with size, top speeds and sensor each."""
    table = Table(show_header=True)
    table.add_column("robot type", no_wrap=True)
    for column in ("size (m)", "top speed", "top turn rate", "ranger"):
        table.add_column(column)
    for name, t in BUILTIN_ROBOT_TYPES.items():
        ranger = (f"{t.ranger.beams} beams, {t.ranger.range:g} m: {t.ranger.name}"
                  if t.ranger.beams else "none")
        table.add_row(name, f"{t.length:g} x {t.width:g}", f"{t.kv:g} m/s",
                      f"{t.kw:.3g} rad/s", ranger)
    Console(highlight=False).print(table)
