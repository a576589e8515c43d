"""The largest counts and times mimics accepts, and the checks that name them.

Every count or time a user gives (robots, beams, seed, steps) is checked here
before anything is allocated or any integer can overflow, so that a value past
a limit is one line naming the field and the limit, never a NumPy error.

>>> check_whole("robots", 3, 1, MAX_ROBOTS)
3
>>> check_whole("seed", -1, 0, MAX_SEED)
Traceback (most recent call last):
...
mimics.world.errors.MimicsError: seed: expected a whole number from 0 to 9223372036854775807, got -1
"""

from __future__ import annotations

import math
import operator
from typing import Any

from mimics.world.errors import MimicsError

#: Robots in one simulation. Far above the Hospital's 2000; memory decides before this does
#: (see ``mimics.records.resources``), this only keeps counts in 32-bit range for the kernels.
MAX_ROBOTS = 10_000_000
#: Beams of one ranger (the Hokuyo has 270; a beam count past this is a typo).
MAX_BEAMS = 100_000
#: Seeds: NumPy takes any integer >= 0, but the battery database (SQLite) and the
#: Parquet columns keep 64-bit signed integers.
MAX_SEED = 2**63 - 1
#: Steps of one run (time limit / dt): step numbers are int64 in the records, and a run
#: this long (68 years at dt = 1 s) is a mistake, not a plan.
MAX_STEPS = 2**31 - 1


def check_whole(name: str, value: Any, minimum: int, maximum: int) -> int:
    """``value`` as an int if it is a whole number in ``[minimum, maximum]``.

    Raises:
        MimicsError: one line naming ``name`` and the range.
    """
    try:
        whole = None if isinstance(value, bool) else operator.index(value)  # int, numpy ints
    except TypeError:
        whole = None
    if whole is None or not minimum <= whole <= maximum:
        raise MimicsError(f"{name}: expected a whole number from {minimum} to {maximum}, "
                          f"got {value!r}")
    return whole


def check_finite(name: str, value: Any) -> Any:
    """``value`` itself, unless it is a float (or holds one) that is NaN or infinite.

    Lists, tuples and dicts are searched, so a sweep ``[1.0, nan]`` is refused too.

    Raises:
        MimicsError: one line naming ``name`` (and the item) and the value.
    """
    if isinstance(value, float) and not math.isfinite(value):
        raise MimicsError(f"{name}: expected a finite number, got {value}")
    if isinstance(value, list | tuple):
        for k, item in enumerate(value):
            check_finite(f"{name}[{k}]", item)
    if isinstance(value, dict):
        for key, item in value.items():
            check_finite(f"{name}.{key}", item)
    return value


def steps_for(duration: float, dt: float) -> int:
    """Whole number of steps covering ``duration``, robust to float error (21.8/0.1 -> 218)."""
    return max(0, math.ceil(duration / dt - 1e-9))


def check_steps(time_limit: float, dt: float) -> int:
    """The step count of a run of ``time_limit`` s at ``dt`` s, if it is within MAX_STEPS.

    Raises:
        MimicsError: the time is not finite or the steps pass MAX_STEPS; the
            message gives the longest time that fits.
    """
    if not math.isfinite(time_limit) or not math.isfinite(dt) or dt <= 0:
        raise MimicsError(f"time: expected a finite number of simulated seconds and dt > 0, "
                          f"got time {time_limit} and dt {dt}")
    steps = time_limit / dt
    if steps > MAX_STEPS:
        raise MimicsError(f"time: {time_limit:g} s at dt = {dt:g} s is {steps:.3g} steps, over "
                          f"the limit of {MAX_STEPS} (expected at most {MAX_STEPS * dt:.6g} s)")
    return steps_for(time_limit, dt)


#: How far past the map's bounds a wall or point a user gives may lie, as a share of the
#: map's larger side (at least :data:`MIN_COORDINATE_MARGIN` m): the grids and the ranger
#: cover the walls, so a wall at 1e300 m would make them overflow, far from the input.
COORDINATE_MARGIN = 1.0
MIN_COORDINATE_MARGIN = 10.0


def coordinate_limits(bounds: tuple[float, ...]) -> tuple[float, float, float, float]:
    """The box ``(xmin, ymin, xmax, ymax)`` coordinates must lie in: the map's ``bounds``
    widened by the margin on every side.

    >>> coordinate_limits((0.0, 0.0, 10.0, 6.0))
    (-10.0, -10.0, 20.0, 16.0)
    """
    xmin, ymin, xmax, ymax = (float(v) for v in bounds)
    margin = max(MIN_COORDINATE_MARGIN, COORDINATE_MARGIN * max(xmax - xmin, ymax - ymin))
    return xmin - margin, ymin - margin, xmax + margin, ymax + margin


def check_coordinates(name: str, points: Any, bounds: tuple[float, ...]) -> None:
    """Refuse coordinates ``(x, y, x, y, ...)`` outside :func:`coordinate_limits`.

    >>> check_coordinates("edit.at", (1e300, 0.0), (0, 0, 10, 6))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    mimics.world.errors.MimicsError: edit.at: expected x from -10 to 20 and y from -10 to 16 ...

    Raises:
        MimicsError: one line naming ``name`` and the allowed ranges.
    """
    values = [float(v) for v in points]
    xlow, ylow, xhigh, yhigh = coordinate_limits(bounds)
    if all(xlow <= x <= xhigh for x in values[0::2]) and all(
            ylow <= y <= yhigh for y in values[1::2]):
        return
    raise MimicsError(f"{name}: expected x from {xlow:g} to {xhigh:g} and y from {ylow:g} to "
                      f"{yhigh:g} (the map's bounds plus a margin), got "
                      f"[{', '.join(f'{v:g}' for v in values)}]")


#: The largest side of a map (m): 1,000 km. A robot moves millimetres per step, which
#: float64 still resolves at :data:`MAX_MAP_COORDINATE`; a side of 1e300 m is a typo.
MAX_MAP_SIDE = 1e6
MAX_MAP_COORDINATE = 1e7


def check_map_extent(name: str, bounds: Any, segments: Any = ()) -> None:
    """Refuse map ``bounds`` ``(xmin, ymin, xmax, ymax)`` whose sides pass
    :data:`MAX_MAP_SIDE` or whose corners lie past :data:`MAX_MAP_COORDINATE`, and wall
    ``segments`` outside the bounds plus the margin of :func:`coordinate_limits`.

    Raises:
        MimicsError: one line naming ``name`` (``map.bounds``, ``map.segments[3]``).
    """
    xmin, ymin, xmax, ymax = (float(v) for v in bounds)
    if not all(abs(v) <= MAX_MAP_COORDINATE for v in (xmin, ymin, xmax, ymax)) or max(
            xmax - xmin, ymax - ymin) > MAX_MAP_SIDE:
        raise MimicsError(f"{name}.bounds: expected sides of at most {MAX_MAP_SIDE:g} m and "
                          f"corners within +-{MAX_MAP_COORDINATE:g} m, got "
                          f"[{xmin:g}, {ymin:g}, {xmax:g}, {ymax:g}]")
    for k, segment in enumerate(segments):
        check_coordinates(f"{name}.segments[{k}]", segment, (xmin, ymin, xmax, ymax))


#: Simulated seconds of one run: the step counter's limit at the default dt = 0.1 s
#: (6.8 years). A run at a smaller dt meets MAX_STEPS first, which ``check_steps`` names.
MAX_TIME = MAX_STEPS * 0.1
#: Wall-clock seconds of a limit or a time-out: what a thread can wait for on every
#: platform (``threading.TIMEOUT_MAX`` is 49.7 days on Windows); longer is a typo.
MAX_WALL_SECONDS = 4_000_000.0
#: Pixels of one side of an image, a frame or a widget: 8192 x 8192 RGBA is 256 MB, what
#: the renderers (Matplotlib's Agg, the video encoder) can allocate.
MAX_IMAGE_SIDE = 8192


def check_number(name: str, value: Any, low: float, high: float, what: str = "a number",
                 *, low_included: bool = False) -> float:
    """``value`` as a float if it is a real number (not a bool or a text) in the range.

    >>> check_number("fps", 1e300, 0, 1000)
    Traceback (most recent call last):
    ...
    mimics.world.errors.MimicsError: fps: expected a positive number (at most 1000), got 1e+300

    Raises:
        MimicsError: one line naming ``name``, what was expected and the value.
    """
    number = math.nan
    if not isinstance(value, bool | str | bytes):
        try:
            number = float(value)
        except (TypeError, ValueError, OverflowError):  # not a number, or an int past floats
            number = math.nan
    above = number >= low if low_included else number > low
    if not (math.isfinite(number) and above and number <= high):
        if low == 0 and not low_included and what.startswith("a number"):
            expected = f"a positive number{what.removeprefix('a number')} (at most {high:g})"
        elif low_included:
            expected = f"{what} from {low:g} to {high:g}"
        else:
            expected = f"{what} above {low:g} and at most {high:g}"
        shown = f"{value:g}" if isinstance(value, float) else repr(value)
        shown = shown if len(shown) <= 60 else shown[:57] + "..."
        raise MimicsError(f"{name}: expected {expected}, got {shown}")
    return number


def check_time(name: str, value: Any) -> float:
    """Simulated seconds of a run: a number above 0 and at most :data:`MAX_TIME`."""
    return check_number(name, value, 0.0, MAX_TIME, "a number of simulated seconds")


def check_wall_seconds(name: str, value: Any) -> float:
    """Wall-clock seconds: a number above 0 and at most :data:`MAX_WALL_SECONDS`."""
    return check_number(name, value, 0.0, MAX_WALL_SECONDS, "a number of wall-clock seconds")


def check_image_side(name: str, value: Any) -> float:
    """Pixels of an image side: a number above 0 and at most :data:`MAX_IMAGE_SIDE`."""
    return check_number(name, value, 0.0, MAX_IMAGE_SIDE, "a number of pixels")
