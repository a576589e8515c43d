"""Arrow's compute kernels that the records use, called without ``pyarrow.compute``.

Importing ``pyarrow.compute`` builds a Python wrapper, with its docstring, for
each of Arrow's hundreds of kernels: 25 to 60 ms at the end of every run that
writes per-robot logs (``Array.cast`` and ``Array.take`` import it too). The
kernels themselves are in ``pyarrow._compute``, loaded with ``pyarrow``, and
``call_function`` (public as ``pyarrow.compute.call_function``) runs any of
them by name: the same kernels, with the options those wrappers would pass.
"""

from __future__ import annotations

import pyarrow as pa

try:  # where pyarrow.compute takes them from (pyarrow 1.0 on)
    from pyarrow._compute import CastOptions, TakeOptions, call_function
except ImportError:  # a pyarrow laid out otherwise: through the public module
    from pyarrow.compute import CastOptions, TakeOptions, call_function


def cast(values: pa.Array, target: pa.DataType) -> pa.Array:
    """``pyarrow.compute.cast(values, target)``: a safe cast."""
    return call_function("cast", [values], CastOptions.safe(target))


def take(values: pa.Array, indices: pa.Array) -> pa.Array:
    """``values.take(indices)``, bounds checked."""
    return call_function("take", [values, indices], TakeOptions(boundscheck=True))


def join_element_wise(*strings: pa.Array | pa.Scalar) -> pa.Array:
    """``pyarrow.compute.binary_join_element_wise``: row by row, the strings joined by
    the last one (a null anywhere gives a null)."""
    return call_function("binary_join_element_wise", list(strings))
