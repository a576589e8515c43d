"""The simulation: state, step and kernels (knows nothing of files, terminals or screens).

Two things about Numba are set up here, before any kernel is compiled or loaded,
because a warm run spends most of its start-up in them:

* **A kernel of mimics loaded from the disk cache does not refresh Numba.**
  Before every cache load Numba refreshes its typing and lowering registries
  (importing about 60 of its modules, cffi's C parser among them, and filling
  its type tables: 0.2 to 0.3 s of CPU, the largest part of a warm run's fixed
  cost), and before every first call it loads the ``numba_extensions`` entry
  points of every installed package (a scan of their metadata, 20 to 30 ms).
  Loaded machine code needs none of that: it needs Numba's runtime (NRT, for
  the arrays it allocates) and its C helpers, registered when the contexts are
  made. So a load of one of mimics' own kernels starts the runtime only; a
  compile (a new signature, a stale cache) still refreshes everything, entry
  points included, as Numba's compiler does that itself before it types
  anything. Other packages' kernels (a user's own ``@njit(cache=True)``) load
  as Numba ships.
* **Numba's BLAS probe is answered by SciPy being installed.** The first
  refresh imports ``numba.np.arraymath``, which checks that BLAS is there by
  importing ``scipy.linalg`` (0.15 to 0.4 s, with NumPy's f2py) for kernels
  that use no BLAS. The engine's kernels use none, so that one check is
  answered by whether SciPy is installed (a dependency, so it is); a kernel
  that does use BLAS (``np.dot`` in a user's own ``@njit``) still gets
  Numba's full check, at its compile, as before. The check is set up at the
  first refresh (a compile), so a run whose kernels all come from the cache
  imports neither ``numba.np.linalg`` nor ``scipy.linalg``.

Both leave the kernels' machine code and results as they are: the same cache
files are loaded, only less of Numba is imported around them. With a Numba
whose internals differ, each step is skipped and Numba behaves as shipped.
"""

from __future__ import annotations

import importlib.util
import sys
from typing import Any


def _defer_numba_blas_check() -> None:
    if "numba.np.arraymath" in sys.modules:  # too late: the check has run
        return
    try:
        from numba.np import linalg
    except ImportError:  # a Numba without this module: nothing to defer
        return
    full_check = getattr(linalg, "ensure_blas", None)
    if full_check is None or getattr(full_check, "deferred_by_mimics", False):
        return
    first = [True]

    def ensure_blas() -> None:
        if first[0]:  # arraymath's import-time probe: "can BLAS be imported?"
            first[0] = False
            if importlib.util.find_spec("scipy") is not None:
                return
        full_check()

    ensure_blas.deferred_by_mimics = True  # type: ignore[attr-defined]
    linalg.ensure_blas = ensure_blas


def _is_ours(py_func: Any) -> bool:
    """Whether a kernel's Python function is one of mimics' own."""
    return str(getattr(py_func, "__module__", "")).startswith("mimics.")


def _set_up_numba() -> None:
    try:
        from numba.core import caching, cpu, dispatcher
        from numba.core.runtime import rtsys
    except ImportError:  # a Numba laid out otherwise: as shipped, BLAS check deferred now
        _defer_numba_blas_check()
        return
    cache_class = caching.Cache
    context_class = cpu.CPUContext
    dispatcher_class = dispatcher.Dispatcher
    has_parts = (all(hasattr(cache_class, name) for name in (
        "load_overload", "_load_overload", "_guard_against_spurious_io_errors"))
        and hasattr(context_class, "load_additional_registries")
        and hasattr(dispatcher_class, "_compilation_chain_init_hook"))
    if not has_parts:
        _defer_numba_blas_check()
        return
    if getattr(cache_class.load_overload, "light_by_mimics", False):  # done already
        return
    load_registries = context_class.load_additional_registries
    full_load = cache_class.load_overload
    init_hook = dispatcher_class._compilation_chain_init_hook

    def load_additional_registries(self: Any) -> None:
        _defer_numba_blas_check()  # before the registries import numba.np.arraymath
        load_registries(self)

    def load_overload(self: Any, sig: Any, target_context: Any) -> Any:
        if not _is_ours(getattr(self, "_py_func", None)):
            return full_load(self, sig, target_context)
        rtsys.initialize(target_context)  # the runtime that the loaded code calls
        with self._guard_against_spurious_io_errors():
            return self._load_overload(sig, target_context)
        # None when the guard swallowed an error: Numba compiles, as it would

    def compilation_chain_init_hook(self: Any) -> None:
        if not _is_ours(getattr(self, "py_func", None)):
            init_hook(self)  # a compile of ours loads the entry points at its refresh

    load_overload.light_by_mimics = True  # type: ignore[attr-defined]
    context_class.load_additional_registries = load_additional_registries
    cache_class.load_overload = load_overload
    dispatcher_class._compilation_chain_init_hook = compilation_chain_init_hook


_set_up_numba()
