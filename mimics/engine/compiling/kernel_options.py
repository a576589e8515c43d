"""The decorator options of kernels that only other kernels call.

Numba gives every compiled function a wrapper that Python can call (and one
that C can call), and compiles both at the function's first compile. A kernel
called only from other kernels never uses them; without them the first run's
compile is shorter (the ray kernel's part: about 1.5 of its 9 s of CPU). Such
kernels are still cached on disk and give the same bits: only the wrappers are
left out. Python must never call one: with no wrapper the call crashes the
interpreter instead of raising (``tests/engine/compiling/test_kernel_options.py`` checks
that no Python code does). Keep ``@njit(cache=True)`` on kernels Python calls.
"""

from __future__ import annotations

INNER = {"cache": True, "no_cpython_wrapper": True, "no_cfunc_wrapper": True}
