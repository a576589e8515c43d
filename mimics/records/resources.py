"""Memory a run will take, estimated from its scenario before anything is allocated.

A team too large for the machine should be one line saying how much it needs
and what to change, not NumPy's ``MemoryError`` half way through allocating
the state (or the operating system killing the process a minute later).

>>> from mimics.scenarios.line import scenario
>>> estimate = run_memory(scenario(robots=1000))
>>> estimate.total > estimate.parts["state and sensors"] > 0
True
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from mimics.engine.ranging.beam_fan import FAN_COLUMNS
from mimics.records.layout import FLUSH_ROWS
from mimics.world.errors import MimicsError
from mimics.world.limits import steps_for
from mimics.world.scenario import Scenario

FLOAT = 8  # bytes of a float64 or an int64
#: Per robot, the float64/int64 columns of ``WorldState`` (pose 3, velocity 2, acceleration 2,
#: goal 2, reference 2, actuation 2, PID integral 2, measured pose 3, velocity 2,
#: acceleration 2, odometry 3, deactivation time, collided with, path length, goal
#: time, user time) and of ``TypeArrays`` (half sizes 2, plant 4, PID gains 6, beam
#: count, range, 7 sigmas).
STATE_COLUMNS = 30 + 21 + FAN_COLUMNS
#: Per robot, Python objects: the memory dict, two message strings, list slots, views.
OBJECT_BYTES = 400
#: Per robot and per beam: the scan (float64) and what each beam hit (int64) in the state,
#: the beam offsets (float64) and their cosines and sines (2 float64) in the types, and
#: one scan-sized temporary while sensing (the noisy scan, the ranger's own buffers).
BEAM_BYTES = 6 * FLOAT
#: A buffered trajectory row: 11 float64 columns plus ids and status as kept by the
#: buffer, then the concatenated columns and the Arrow table built from them at a flush.
ROW_BYTES = 3 * (12 * FLOAT + 1)
#: Fixed cost of the interpreter, NumPy, Numba's kernels and Arrow (measured: about 250 MB).
BASE_BYTES = 300 * 2**20


@dataclass(frozen=True)
class MemoryEstimate:
    """The bytes a run needs, in total and by part (the parts say what to change)."""

    total: int
    parts: dict[str, int]

    def largest(self) -> str:
        """The name of the largest part that depends on the run (the base does not)."""
        return max((name for name in self.parts if name != "base"),
                   key=lambda name: self.parts[name])


def run_memory(scenario: Scenario, *, flush_rows: int = FLUSH_ROWS, every: int = 1,
               time: float | None = None) -> MemoryEstimate:
    """Bytes a run of ``scenario`` needs, from its sizes alone (nothing is allocated).

    With ``n`` robots, ``B`` beams (the most of any type), ``D`` and ``L`` the
    deadlock and livelock windows in steps, ``F`` the recorder's ``flush_rows``
    and ``R`` the rows the whole run records (``n`` per recorded step)::

        state and sensors = n * (8 * STATE_COLUMNS + OBJECT_BYTES + BEAM_BYTES * B)
        stall windows     = n * 8 * (2 * (D + 1) + (L + 1))
        recorder buffer   = ROW_BYTES * (min(F, R) + n)  (rows kept until a part is written)
        base              = BASE_BYTES              (interpreter, NumPy, Numba, Arrow)

    Args:
        scenario: the scenario to run.
        flush_rows: the recorder's rows per part (``run_to_folder``).
        every: the recorder's step interval: every ``every``-th step is recorded.
        time: the run's simulated seconds (default: the scenario's time limit).

    Returns:
        The estimate, by part.
    """
    if every < 1:
        raise MimicsError(f"every: expected a whole number >= 1, got {every!r}")
    n = scenario.robot_count
    beams = max((t.ranger.beams for t in scenario.types), default=0)
    settings = scenario.settings
    deadlock = max(1, steps_for(settings.deadlock_window, settings.dt))
    livelock = max(1, steps_for(settings.livelock_window, settings.dt))
    steps = steps_for(settings.time_limit if time is None else time, settings.dt)
    rows = n * (steps // every + 2)  # the first and last steps too
    parts = {
        "state and sensors": n * (FLOAT * STATE_COLUMNS + OBJECT_BYTES + BEAM_BYTES * beams),
        "stall windows": n * FLOAT * (2 * (deadlock + 1) + (livelock + 1)),
        "recorder buffer": ROW_BYTES * (min(flush_rows, rows) + n),
        "base": BASE_BYTES,
    }
    return MemoryEstimate(sum(parts.values()), parts)


def available_memory() -> int | None:
    """Bytes the machine can give now without swapping, or None when it cannot be told.

    Linux: ``MemAvailable`` in ``/proc/meminfo``; elsewhere ``os.sysconf``'s free
    physical pages (macOS has none of either: None, and nothing is refused).
    """
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


ADVICE = {
    "state and sensors": "fewer robots or fewer beams per ranger",
    "stall windows": "shorter settings.deadlock_window and livelock_window, or a larger dt",
    "recorder buffer": "a smaller flush_rows for the recorder, or fewer robots",
}


def check_memory(scenario: Scenario, *, flush_rows: int = FLUSH_ROWS, every: int = 1,
                 time: float | None = None, available: int | None = None) -> MemoryEstimate:
    """Refuse a run that needs more memory than the machine has.

    Args:
        scenario: the scenario to run.
        flush_rows: the recorder's rows per part.
        every: the recorder's step interval.
        time: the run's simulated seconds (default: the scenario's time limit).
        available: bytes available (default: :func:`available_memory`).

    Returns:
        The estimate, when it fits (or when the memory available is unknown).

    Raises:
        MimicsError: one line with the figure needed, the figure available, and what
            to change.
    """
    estimate = run_memory(scenario, flush_rows=flush_rows, every=every, time=time)
    available = available_memory() if available is None else available
    if available is not None and estimate.total > available:
        largest = estimate.largest()
        beams = max((t.ranger.beams for t in scenario.types), default=0)
        raise MimicsError(
            f"scenario {scenario.name!r}: this run needs about {size_text(estimate.total)} "
            f"({largest}: {size_text(estimate.parts[largest])} for {scenario.robot_count} robots "
            f"with {beams} beams), more than the {size_text(available)} available: use "
            f"{ADVICE[largest]}")
    return estimate


def size_text(count: int) -> str:
    """A byte count for a person: ``"1.5 GB"``."""
    for unit, scale in (("TB", 2**40), ("GB", 2**30), ("MB", 2**20)):
        if count >= scale:
            amount = count / scale
            # a setting such as deadlock_window = 1e300 asks for a 290-digit number of TB
            return f"{amount:.3g} {unit}" if amount >= 1e6 else f"{amount:.1f} {unit}"
    return f"{count / 2**10:.1f} kB"
