"""What ``mimics run`` and ``mimics ros`` share: reading ``--param``, the summary table,
``--video``."""

from __future__ import annotations

import tomllib
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.table import Table

from mimics.interfaces.cli.output import fail
from mimics.world.errors import MimicsError

console = Console(emoji=False)  # names print as given (and no emoji table to load)


def parse_params(items: list[str]) -> dict[str, Any]:
    """``["robots=200", "x_offset=0.5"]`` to a dict, values read as TOML literals."""
    params: dict[str, Any] = {}
    for item in items:
        key, sep, text = item.partition("=")
        if not sep or not key.strip():
            raise MimicsError(f"--param {item!r}: expected NAME=VALUE")
        try:
            value = tomllib.loads(f"v = {text}")["v"]
        except tomllib.TOMLDecodeError:
            value = text
        params[key.strip()] = value
    return params


def check_repeated(params: dict[str, Any], *, robots: int | None = None,
                   time: float | None = None) -> None:
    """Refuse an option and a ``--param`` that give two values for the same thing.

    Raises:
        MimicsError: naming both (``--robots 3 and --param robots=7``).
    """
    for option, key, value in (("--robots", "robots", robots), ("--time", "time_limit", time)):
        if value is not None and key in params and params[key] != value:
            raise MimicsError(f"{option} {value:g} and --param {key}={params[key]!r}: two values "
                              f"for the same parameter; give one")


def _time_to_goal(summary: dict[str, Any]) -> list[tuple[str, str]]:
    """The restricted mean time to goal, for runs whose robots have goals."""
    arrivals = summary.get("arrivals") or {}
    if arrivals.get("restricted_mean") is None:
        return []
    return [("time to goal", f"{arrivals['restricted_mean']:.2f} s ({arrivals['arrived']} of "
             f"{arrivals['goal_robots']} arrived by the {arrivals['horizon']:g} s horizon)")]


def print_summary(summary: dict[str, Any], out: Path | None) -> None:
    """A short table of a run's outcome."""
    table = Table(title=f"{summary['scenario']} / {summary['algorithm']} / seed "
                        f"{summary['seed']}: {summary['status']}", show_header=False)
    table.add_column(style="bold")
    table.add_column(justify="right")
    rows = [("robots", summary["robots"]), ("reached goal", summary["reached_goal"]),
            ("collisions", summary["collisions"]), ("escaped", summary["escaped"]),
            ("deadlocks", summary["deadlocks"]), ("livelocks", summary["livelocks"]),
            ("exceptions", summary["exceptions"]),
            *_time_to_goal(summary),
            ("simulated time", f"{summary['sim_time']:.2f} s"),
            ("wall time", f"{summary['wall_time']:.2f} s"),
            ("speed", f"{summary['sim_speed']:.2f} s_sim/s" if summary["sim_speed"] else "-")]
    from mimics.engine.compiling import compile_seconds

    # kernels compiled by this process (or the run's child, for C): not the run's own time
    compiled = max(compile_seconds(), float(summary.get("compile_time") or 0.0))
    if compiled >= 0.05:
        rows.append(("compile", f"{compiled:.1f} s (first run: kernels cached for later runs)"))
    for name, value in rows:
        table.add_row(name, str(value))
    console.print(table)
    if summary.get("error"):
        # not wrapped: the first line names file:line, the second is the source line
        console.print(f"error: {summary['error']}", markup=False, highlight=False,
                      soft_wrap=True)
    if out is not None:
        console.print(f"records in {out}", markup=False)


def export_video(folder: Path, video: Path) -> None:
    """``--video``: the finished run's replay as a video file (exit 2 if it cannot be made)."""
    from mimics.interfaces.replay import export_replay

    try:
        export_replay(folder, video=video)
    except MimicsError as exc:
        raise fail(str(exc)) from None
