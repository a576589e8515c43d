"""The simulation: state, step and kernels (knows nothing of files, terminals or screens).

One thing is set up here, before any kernel is compiled or loaded: Numba's
first kernel of a process imports ``numba.np.arraymath``, which checks that
BLAS is there by importing ``scipy.linalg`` (0.15 to 0.4 s, with NumPy's
f2py, for kernels that use no BLAS). The engine's kernels use none, so that
one check is answered by whether SciPy is installed (a dependency, so it is);
a kernel that does use BLAS (``np.dot`` in a user's own ``@njit``) still gets
Numba's full check, at its compile, as before.
"""

from __future__ import annotations

import importlib.util
import sys


def _defer_numba_blas_check() -> None:
    if "numba.np.arraymath" in sys.modules:  # too late: the check has run
        return
    try:
        from numba.np import linalg
    except ImportError:  # a Numba without this module: nothing to defer
        return
    full_check = getattr(linalg, "ensure_blas", None)
    if full_check is None:
        return
    first = [True]

    def ensure_blas() -> None:
        if first[0]:  # arraymath's import-time probe: "can BLAS be imported?"
            first[0] = False
            if importlib.util.find_spec("scipy") is not None:
                return
        full_check()

    linalg.ensure_blas = ensure_blas


_defer_numba_blas_check()
