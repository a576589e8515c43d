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
