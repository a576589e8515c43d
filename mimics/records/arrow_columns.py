"""Arrow arrays made from NumPy buffers, as the recorder writes them.

``pyarrow.array`` imports pandas at its first call, whatever its argument
(it asks whether the argument is a pandas object): about 0.4 s at the end of
every run that only records. The recorder's columns are NumPy arrays of
Arrow's fixed-width types and lists of Python strings, which these functions
hand to Arrow as buffers instead: the same arrays, without pandas.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pyarrow as pa

_NUMPY_TYPES = {pa.float64(): np.float64, pa.float32(): np.float32, pa.int64(): np.int64,
                pa.int32(): np.int32, pa.int16(): np.int16, pa.int8(): np.int8,
                pa.uint16(): np.uint16, pa.uint8(): np.uint8}
_OFFSET_LIMIT = np.iinfo(np.int32).max  # string offsets are int32


def numeric_array(values: np.ndarray | Sequence[float], type: pa.DataType) -> pa.Array:
    """``values`` as an Arrow array of ``type`` (a bool or fixed-width number type).

    Raises:
        OverflowError: when a Python integer does not fit ``type``.
        TypeError: when ``type`` is not one of those, or an array's values are of
            another kind (floats for an integer type, say).
    """
    if type == pa.bool_():
        flags = np.asarray(values, dtype=bool)
        bits = np.packbits(flags, bitorder="little")  # Arrow's booleans: one bit each, LSB first
        return pa.Array.from_buffers(type, flags.size, [None, pa.py_buffer(bits)])
    dtype = _NUMPY_TYPES.get(type)
    if dtype is None:
        raise TypeError(f"numeric_array: no NumPy type for Arrow's {type}")
    if isinstance(values, np.ndarray) and not np.can_cast(values.dtype, dtype, "same_kind"):
        raise TypeError(f"numeric_array: {values.dtype} values would not keep their "
                        f"meaning as {type}")  # floats truncated to integers, say
    data = np.ascontiguousarray(values, dtype=dtype)
    return pa.Array.from_buffers(type, data.size, [None, pa.py_buffer(data)])


def string_array(values: Sequence[str]) -> pa.Array | pa.ChunkedArray:
    """``values`` (Python strings, none missing) as an Arrow ``string`` array."""
    encoded = [value.encode() for value in values]
    ends = np.cumsum([len(data) for data in encoded], dtype=np.int64)
    if ends.size and ends[-1] > _OFFSET_LIMIT:
        return pa.array(values, pa.string())  # over 2 GiB of text: Arrow chunks it
    offsets = np.zeros(len(encoded) + 1, dtype=np.int32)
    offsets[1:] = ends
    return pa.Array.from_buffers(pa.string(), len(encoded),
                                 [None, pa.py_buffer(offsets), pa.py_buffer(b"".join(encoded))])


def column_array(values: np.ndarray | Sequence[object],
                 type: pa.DataType) -> pa.Array | pa.ChunkedArray:
    """A column of ``type``: strings or numbers (see the two functions above)."""
    if type == pa.string():
        return string_array(values)  # type: ignore[arg-type]
    return numeric_array(values, type)  # type: ignore[arg-type]


def numpy_column(column: pa.Array | pa.ChunkedArray) -> np.ndarray:
    """A column of a fixed-width number type as a NumPy array (``to_numpy`` imports pandas).

    A column of one chunk comes as a read-only view of Arrow's buffer, not a copy
    (the robot logs read 14 columns of the whole trajectory: 7 MB not copied at
    the end of a 100-robot Cave run).

    Raises:
        TypeError: when the column is of another type or has missing values.
    """
    dtype = _NUMPY_TYPES.get(column.type)
    if dtype is None or column.null_count:
        raise TypeError(f"numpy_column: expected numbers of {sorted(map(str, _NUMPY_TYPES))} "
                        f"with none missing, got {column.type} ({column.null_count} missing)")
    chunks = column.chunks if isinstance(column, pa.ChunkedArray) else [column]
    size = np.dtype(dtype).itemsize
    parts = [np.frombuffer(chunk.buffers()[1], dtype, len(chunk), chunk.offset * size)
             for chunk in chunks if len(chunk)]
    if len(parts) == 1:
        return parts[0]
    return np.concatenate(parts) if parts else np.empty(0, dtype)


def empty_table(schema: pa.Schema) -> pa.Table:
    """A table of ``schema`` with no row (``Schema.empty_table`` imports pandas)."""
    return pa.Table.from_batches([], schema=schema)
