"""``larger`` and ``smaller`` give, to the bit, what Python's ``max`` and ``min`` give
inside a kernel (Numba's own) and in Python: NaN where it comes first, signed zeros
by their order, mixed ints and floats in their common type."""

import math
import struct

from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller


@njit(cache=False)
def _ours(a, b, c, i):  # pragma: no cover - compiled
    return (larger(a, b), smaller(a, b), larger(a, b, c), smaller(c, a, b), larger(i, a),
            smaller(a, i), larger(1, i), smaller(i, 2))


@njit(cache=False)
def _numbas(a, b, c, i):  # pragma: no cover - compiled
    return max(a, b), min(a, b), max(a, b, c), min(c, a, b), max(i, a), min(a, i), \
        max(1, i), min(i, 2)


def _python(a, b, c, i):
    return (max(a, b), min(a, b), max(a, b, c), min(c, a, b), float(max(i, a)),
            float(min(a, i)), max(1, i), min(i, 2))


def _bits(values):
    return [struct.pack("<d", v) if isinstance(v, float) else v for v in values]


floats = st.one_of(st.floats(allow_nan=True, allow_infinity=True),
                   st.sampled_from([0.0, -0.0, math.nan, 1.0, -1.0]))


@settings(max_examples=300, deadline=None)
@given(floats, floats, floats, st.integers(-2**40, 2**40))
def test_larger_and_smaller_match_max_and_min(a, b, c, i):
    ours, numbas = _ours(a, b, c, i), _numbas(a, b, c, i)
    assert _bits(ours) == _bits(numbas)
    assert [type(v) for v in ours] == [type(v) for v in numbas]
    python = _python(a, b, c, i)
    for got, want in zip(ours, python, strict=True):
        assert got == want or (math.isnan(got) and math.isnan(want))
