"""Numbers in the per-robot logs: formatted once per run of equal values, read back exactly."""

import math

import numpy as np
import pyarrow as pa
import pyarrow.compute as pc
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from mimics.records.log_texts import number_texts as _texts
from mimics.records.log_texts import time_texts as _time_texts

# values a log holds: any double, with long runs of repeats (robots standing still)
doubles = st.floats(allow_nan=True, allow_infinity=True, width=64)
runs = st.lists(st.tuples(doubles, st.integers(1, 40)), min_size=0, max_size=30)


def one_by_one(values: np.ndarray) -> list[str]:
    """The reference: every value formatted on its own."""
    return [pc.cast(pa.array([v], pa.float64()), pa.string())[0].as_py() for v in values]


def as_array(pairs: list[tuple[float, int]]) -> np.ndarray:
    return np.array([v for v, count in pairs for _ in range(count)], dtype=np.float64)


@settings(max_examples=200, deadline=None)
@given(pairs=runs)
def test_runs_of_equal_values_are_formatted_as_each_value_alone(pairs):
    values = as_array(pairs)
    texts = _texts(values).to_pylist()
    assert texts == one_by_one(values)
    for value, text in zip(values, texts, strict=True):  # read back bit for bit
        back = float(text)
        assert (math.isnan(value) and math.isnan(back)) or (
            np.float64(back).tobytes() == np.float64(value).tobytes())


@settings(max_examples=100, deadline=None)
@given(values=arrays(np.float64, st.integers(0, 300), elements=doubles))
def test_values_without_runs_are_formatted_as_each_value_alone(values):
    assert _texts(values).to_pylist() == one_by_one(values)


@settings(max_examples=100, deadline=None)
@given(steps=st.lists(st.integers(0, 50), max_size=200), dt=st.sampled_from([0.1, 0.05, 1 / 3]),
       odd=st.booleans())
def test_time_is_formatted_once_per_step_or_row_by_row_when_steps_disagree(steps, dt, odd):
    steps = np.sort(np.array(steps, dtype=np.int64))
    time = steps * dt
    if odd and time.size:
        time[-1] += 1e-3  # a time that is not its step's: every row formatted on its own
    assert _time_texts(time, steps).to_pylist() == one_by_one(time)
