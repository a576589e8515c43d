"""The recorder's Arrow arrays equal pyarrow.array's, and a recorded run never imports pandas."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pyarrow as pa
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from mimics.records.arrow_columns import (
    column_array,
    empty_table,
    numeric_array,
    numpy_column,
    string_array,
)
from mimics.records.events import EVENTS_SCHEMA
from mimics.records.trajectory import TRAJECTORY_SCHEMA

# pyarrow.array, the reference, imports pandas at its first call: no deadline
NO_DEADLINE = settings(deadline=None)

NUMBER_TYPES = [(pa.float64(), np.float64), (pa.float32(), np.float32), (pa.int64(), np.int64),
                (pa.int32(), np.int32), (pa.int8(), np.int8), (pa.uint16(), np.uint16)]


@pytest.mark.parametrize(("arrow_type", "dtype"), NUMBER_TYPES)
@given(data=st.data())
@NO_DEADLINE
def test_numbers_equal_pyarrows_own_bit_for_bit(arrow_type: pa.DataType, dtype: type,
                                                data: st.DataObject) -> None:
    values = data.draw(arrays(dtype, st.integers(0, 40)))  # NaN, inf and -0.0 included
    ours, theirs = numeric_array(values, arrow_type), pa.array(values, arrow_type)
    assert ours.type == theirs.type and len(ours) == len(theirs) and ours.null_count == 0
    unsigned = np.dtype(f"u{np.dtype(dtype).itemsize}")
    assert np.array_equal(numpy_column(ours).view(unsigned), theirs.to_numpy().view(unsigned))


@given(st.lists(st.booleans(), max_size=70))
@NO_DEADLINE
def test_booleans_equal_pyarrows_own(flags: list[bool]) -> None:
    ours = numeric_array(np.array(flags, dtype=bool), pa.bool_())
    assert ours.equals(pa.array(flags, pa.bool_()))
    assert ours.to_pylist() == flags


@given(st.lists(st.text(), max_size=20))
@NO_DEADLINE
def test_strings_equal_pyarrows_own(texts: list[str]) -> None:
    ours = string_array(texts)
    assert ours.equals(pa.array(texts, pa.string()))
    assert ours.to_pylist() == texts


@given(st.lists(st.integers(-2**31, 2**31 - 1), max_size=30), st.integers(0, 5))
@NO_DEADLINE
def test_numpy_column_reads_chunks_and_slices(values: list[int], skip: int) -> None:
    column = pa.chunked_array([pa.array(values, pa.int32())[skip:], pa.array(values, pa.int32())],
                              pa.int32())
    assert numpy_column(column).tolist() == values[skip:] + values
    assert numpy_column(column).dtype == np.int32
    alone = numpy_column(pa.array(values, pa.int32())[skip:])  # one chunk: a view of it
    assert alone.tolist() == values[skip:] and alone.dtype == np.int32


def test_what_the_columns_refuse() -> None:
    with pytest.raises(OverflowError):
        column_array([2**40], pa.int32())
    with pytest.raises(TypeError, match="would not keep their meaning"):
        numeric_array(np.array([1.5]), pa.int32())
    with pytest.raises(TypeError, match="no NumPy type"):
        numeric_array([1.0], pa.float16())
    with pytest.raises(TypeError, match="got string"):
        numpy_column(pa.array(["a"]))
    with pytest.raises(TypeError, match="1 missing"):
        numpy_column(pa.array([1.0, None]))


def test_empty_tables_equal_pyarrows_own() -> None:
    for schema in (TRAJECTORY_SCHEMA, EVENTS_SCHEMA,
                   pa.schema([("beams", pa.list_(pa.uint16()))])):
        assert empty_table(schema).equals(schema.empty_table())


def test_a_recorded_run_with_logs_and_scans_never_imports_pandas(tmp_path) -> None:
    # pandas costs about 0.4 s to import: a run that only records should not pay it
    script = f"""
import sys
from mimics.records.runner import prepare, run_to_folder
result = run_to_folder(prepare("obstacle_room", "dispersion", robots=4, time=2, seed=3),
                       {str(tmp_path / "run")!r}, robot_logs="on", record_scans=True)
print(result.status, "pandas" in sys.modules)
"""
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          check=False, timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["time_limit", "False"]
    assert (tmp_path / "run" / "robots" / "robot_0000.log").exists()
    assert (tmp_path / "run" / "scans.parquet").exists()
