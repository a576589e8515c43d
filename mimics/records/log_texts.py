"""Numbers as the per-robot logs print them: Arrow's shortest exact text.

Formatting is most of the cost of the logs: values repeated in consecutive
rows, and a step's time shared by all its robots, are formatted once.
"""

from __future__ import annotations

import numpy as np
import pyarrow as pa

from mimics.records.arrow_columns import numeric_array
from mimics.records.arrow_compute import cast, take

#: A column is formatted run by run when it has at most this share of runs of equal values.
_RUN_SHARE = 0.5


def number_texts(values: np.ndarray) -> pa.Array:
    """``values`` as text in their shortest exact form (Arrow's: ``1``, ``0.1``, ``1e-7``).

    Formatting is most of the cost of the logs, so a value repeated in
    consecutive rows (a robot standing still) is formatted once when that
    saves work. Values are compared bit for bit: ``-0.0`` prints apart from ``0.0``.
    """
    bits = values.view(np.int64)
    new = np.empty(values.size, dtype=bool)
    new[:1] = True
    np.not_equal(bits[1:], bits[:-1], out=new[1:])
    if np.count_nonzero(new) > _RUN_SHARE * values.size:
        return cast(numeric_array(values, pa.float64()), pa.string())
    return take(cast(numeric_array(values[new], pa.float64()), pa.string()),
                numeric_array(np.cumsum(new) - 1, pa.int64()))


def time_texts(time: np.ndarray, steps: np.ndarray) -> pa.Array:
    """The time column as text, each step's time formatted once (all its robots share it)."""
    if time.size == 0 or steps.min() < 0:
        return number_texts(time)
    present = np.zeros(int(steps.max()) + 1, dtype=bool)
    present[steps] = True
    place = (np.cumsum(present) - 1)[steps]  # each row's step among the steps present
    step_time = np.empty(int(np.count_nonzero(present)))
    step_time[place] = time
    if not same_bits(step_time[place], time):  # not one time per step: format every row
        return number_texts(time)
    return take(cast(numeric_array(step_time, pa.float64()), pa.string()),
                numeric_array(place, pa.int64()))


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two float64 arrays hold the same bits (so the same text, ``nan`` included)."""
    return a.shape == b.shape and bool(np.array_equal(a.view(np.int64), b.view(np.int64)))
