"""One place where every value given on the command line is checked: numbers and text.

Before any command runs, :func:`guard_values` walks the whole command tree
(also commands added later by other modules) and gives every parameter a
check of the values it receives, after Typer has converted them:

* every text and path must be valid UTF-8 (a file name from a non-UTF-8 file
  system would otherwise fail deep in a writer, after the work is done);
* every float must be finite (``nan``, ``inf`` and overflowing literals such as
  ``1e999`` are refused);
* every integer must fit in 64 bits (``2**63 - 1``);
* options with a known meaning, found by name in :data:`RANGES`, must also be in
  their range (``--robots`` from 1 to ``MAX_ROBOTS``, ``--seed`` from 0 to
  ``MAX_SEED``, ``--fps`` above 0...).

A value outside is a usage error: one line ``mimics: error: Invalid value for
'--seed': ...`` and exit status 2, before the command starts. Commands keep
their own checks of what only they know (a choice of words, a file that must
exist); this module makes a NumPy overflow, a NaN or an unencodable name
reaching a command impossible.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import PurePath
from typing import Any

import typer

from mimics.world.limits import MAX_IMAGE_SIDE, MAX_ROBOTS, MAX_SEED, MAX_TIME, MAX_WALL_SECONDS

INT64_MAX = 2**63 - 1


@dataclass(frozen=True)
class Range:
    """Accepted values of an option: ``low < value`` (or ``<=`` when ``closed``), ``<= high``."""

    low: float
    high: float
    closed: bool = True  # whether ``low`` itself is accepted

    def describe(self) -> str:
        """``"from 1 to 10"``, ``"above 0 and at most 8192"``."""
        high = f"{self.high:g}" if isinstance(self.high, float) else str(self.high)
        low = f"{self.low:g}" if isinstance(self.low, float) else str(self.low)
        return f"from {low} to {high}" if self.closed else f"above {low} and at most {high}"

    def holds(self, value: float) -> bool:
        """Whether ``value`` is accepted."""
        above = value >= self.low if self.closed else value > self.low
        return above and value <= self.high


POSITIVE = Range(0.0, 1e15, closed=False)
SIM_TIME = Range(0.0, MAX_TIME, closed=False)
WALL_TIME = Range(0.0, MAX_WALL_SECONDS, closed=False)
PIXELS = Range(0.0, float(MAX_IMAGE_SIDE), closed=False)
#: Options by name (the Python parameter name: ``--wall-limit`` is ``wall_limit``) whose
#: values have one meaning in every command that has them.
RANGES: dict[str, Range] = {
    "robots": Range(1, MAX_ROBOTS),
    "seed": Range(0, MAX_SEED),
    "workers": Range(1, 4096),
    "time": SIM_TIME, "time_": SIM_TIME, "timeout": WALL_TIME, "wall_limit": WALL_TIME,
    "fps": Range(0.0, 1000.0, closed=False),
    "speed": POSITIVE,
    "scale": POSITIVE, "resolution": POSITIVE, "tolerance": Range(0.0, 1e15),
    "size": POSITIVE,
    "width": PIXELS, "height": PIXELS,
    "trail": Range(0.0, 1e15),
    "robot": Range(0, MAX_ROBOTS - 1), "robot_beams": Range(0, MAX_ROBOTS - 1),
    "port": Range(0, 65535),
}


def check_value(name: str, value: Any) -> str | None:
    """Why ``value`` (a number, a text, or a list or tuple of them) is refused for ``name``.

    >>> check_value("seed", -1)
    'expected a whole number from 0 to 9223372036854775807, got -1'
    >>> check_value("scale", float("nan"))
    'expected a finite number, got nan'
    >>> check_value("anything", 3) is None
    True
    """
    for text in _texts(value):
        try:
            text.encode("utf-8")
        except UnicodeEncodeError:
            return f"expected text in UTF-8, got {text.encode('utf-8', 'replace').decode()!r}"
    for number in _numbers(value):
        if isinstance(number, float) and not math.isfinite(number):
            return f"expected a finite number, got {number}"
        if isinstance(number, int) and not -INT64_MAX <= number <= INT64_MAX:
            return f"expected a whole number from {-INT64_MAX} to {INT64_MAX}, got {number}"
        limits = RANGES.get(name)
        if limits is not None and not limits.holds(number):
            kind = "a whole number" if isinstance(number, int) else "a number"
            return f"expected {kind} {limits.describe()}, got {number:g}" if isinstance(
                number, float) else f"expected {kind} {limits.describe()}, got {number}"
    return None


def _numbers(value: Any) -> Iterator[int | float]:
    if isinstance(value, bool) or value is None:
        return
    if isinstance(value, int | float):
        yield value
    elif isinstance(value, list | tuple):
        for item in value:
            yield from _numbers(item)


def _texts(value: Any) -> Iterator[str]:
    if isinstance(value, str | PurePath):
        yield str(value)
    elif isinstance(value, list | tuple):
        for item in value:
            yield from _texts(item)


def _checked(name: str, callback: Callable[..., Any] | None) -> Callable[..., Any]:
    def check(ctx: Any, param: Any, value: Any) -> Any:
        problem = check_value(name, value)
        if problem is not None:
            raise typer.BadParameter(problem, ctx=ctx, param=param)
        return callback(ctx, param, value) if callback is not None else value

    check.guards_values = True  # type: ignore[attr-defined]
    return check


def guard_values(command: Any) -> None:
    """Give every parameter of ``command`` and of its sub-commands the value check."""
    for param in getattr(command, "params", ()):
        if param.name and not getattr(param.callback, "guards_values", False):
            param.callback = _checked(param.name, param.callback)
    for sub in getattr(command, "commands", {}).values():
        guard_values(sub)
