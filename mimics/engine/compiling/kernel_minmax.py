"""``larger`` and ``smaller``: Python's ``max`` and ``min`` of numbers, inside kernels.

Numba compiles its builtin ``max(a, b)`` as a function of its own for each tuple of
argument types, in each process (40 to 60 ms each: about a second of CPU of a first
run's compile, ``benchmarks/NOTES.md``). These intrinsics emit at the call the very
instructions that function holds (Numba's ``do_minmax``: the values in their common
type, each compared with the best so far, in order, so that NaN and signed zeros come
out as ``max`` and ``min`` give them; tested against both).
"""

from __future__ import annotations

import operator
from typing import Any

from numba.core import cgutils, types
from numba.core.typing import signature
from numba.cpython.builtins import do_minmax
from numba.extending import intrinsic


def _typed(typingctx: Any, values: tuple[Any, ...], compare: Any) -> Any:
    """The signature and code of ``max`` (``compare`` is ``>``) or ``min`` (``<``)."""
    if not values or not all(isinstance(v, (types.Number, types.Boolean)) for v in values):
        return None  # Numba then reports the call as untyped
    common = typingctx.unify_types(*values)

    def codegen(context: Any, builder: Any, sig: Any, args: Any) -> Any:
        return do_minmax(context, builder, list(sig.args[0]),
                         cgutils.unpack_tuple(builder, args[0]), compare)
    return signature(common, types.StarArgTuple.from_types(values)), codegen


@intrinsic
def larger(typingctx: Any, *values: Any) -> Any:
    """``max(*values)`` of numbers, compiled at the call (kernels only)."""
    return _typed(typingctx, values, operator.gt)


@intrinsic
def smaller(typingctx: Any, *values: Any) -> Any:
    """``min(*values)`` of numbers, compiled at the call (kernels only)."""
    return _typed(typingctx, values, operator.lt)
