"""How the engine sets Numba up, before any kernel is compiled or loaded.

A warm run spends most of its start-up around Numba's cached kernels rather
than in them, so these things are changed:

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
* **Numba's BLAS probe is answered by SciPy being installed.** Importing
  ``numba.np.arraymath`` (the first refresh does; so does loading a cached
  kernel that uses one of its functions, as the still scans' do) checks that
  BLAS is there by importing ``scipy.linalg`` (0.15 to 0.4 s, with NumPy's
  f2py) for kernels that use no BLAS. The engine's kernels use none, so that
  one check is answered by whether SciPy is installed (a dependency, so it
  is); a kernel that does use BLAS (``np.dot`` in a user's own ``@njit``)
  still gets Numba's full check, at its compile, as before. The check is
  deferred by an import hook just before ``numba.np.arraymath`` is first
  imported, so a run that never imports it imports ``numba.np.linalg``
  neither (45 ms).
* **Numba's runtime is loaded from the disk, not compiled, in every process.**
  Starting the runtime (NRT) compiles a small LLVM module of atomic counters
  and reference counting (40 to 50 ms of CPU in each process). Its machine
  code is kept beside the engine's kernels, keyed as Numba keys them (Numba's
  and llvmlite's versions, the target, the CPU and its features), and loaded
  as a cached kernel is; the first process of an install compiles it as Numba
  does and writes it.

* **Numba's import skips two imports it only needs for a check.** Numba imports
  SciPy to check that its version is at least 1.0 (the project requires a
  newer one) and PyYAML to read a ``.numba_config.yaml`` that is not there:
  10 to 40 ms of a warm run, skipped (the first import of each by Numba's own
  module fails once; a config file in the working folder keeps PyYAML's).

* **A kernel of mimics loads with less of Numba around it**
  (:mod:`mimics.engine.compiling.numba_library_loads`): its names from its machine code,
  Numba's implementations it inlined without their modules, no lock events.

All leave the kernels' machine code and results as they are: the same cache
files are loaded, only less of Numba is imported or compiled around them. With
a Numba whose internals differ, each change is skipped and Numba behaves as
shipped.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import os
import pickle
import sys
import tempfile
from pathlib import Path
from typing import Any

from mimics.engine.compiling.numba_library_loads import (
    environments_without_imports,
    link_modules_when_needed,
    loading_ours,
)
from mimics.engine.compiling.patch_record import record


def _defer_numba_blas_check() -> None:
    if "numba.np.arraymath" in sys.modules:  # too late: the check has run
        return
    try:
        from numba.np import linalg
    except ImportError:  # a Numba without this module: nothing to defer
        record("blas_probe_deferred", False)
        return
    full_check = getattr(linalg, "ensure_blas", None)
    if full_check is None or getattr(full_check, "deferred_by_mimics", False):
        record("blas_probe_deferred", full_check is not None)
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
    record("blas_probe_deferred", True)


def _is_ours(py_func: Any) -> bool:
    """Whether a kernel's Python function is one of mimics' own."""
    return str(getattr(py_func, "__module__", "")).startswith("mimics.")


class _BeforeArraymath:
    """An import hook: defers the BLAS probe just before ``numba.np.arraymath`` is first
    imported (by the first refresh, or by a cached kernel whose environment names one of
    its functions), then leaves ``sys.meta_path``."""

    def find_spec(self, name: str, path: Any = None, target: Any = None) -> None:
        if name == "numba.np.arraymath":
            with contextlib.suppress(ValueError):
                sys.meta_path.remove(self)
            _defer_numba_blas_check()
        return None  # the import goes on as usual


class _SkippedByNumba:
    """An import hook: the first import of a module by one module of Numba fails (Numba
    handles that: it skips a check), every other import of it goes on as usual."""

    def __init__(self, skipped: dict[str, str]) -> None:
        self.skipped = dict(skipped)  # module -> the Numba module whose import of it fails

    def find_spec(self, name: str, path: Any = None, target: Any = None) -> None:
        importer = self.skipped.get(name)
        if importer is not None and _imported_by(importer):
            del self.skipped[name]
            raise ModuleNotFoundError(f"{name}: skipped by mimics in {importer}", name=name)
        return None


def _imported_by(module: str) -> bool:
    """Whether the import under way is a statement of ``module`` (its frame is on the
    stack, below the import machinery's own frames)."""
    frame = sys._getframe(2)
    for _ in range(12):
        if frame is None:
            return False
        if frame.f_globals.get("__name__") == module:
            return True
        frame = frame.f_back
    return False


def _import_numba() -> None:
    """Import Numba, skipping its SciPy version check and, with no config file here,
    PyYAML (see the module's docstring)."""
    if "numba" in sys.modules:
        return
    skipped = {"scipy": "numba"}
    if not os.path.isfile(".numba_config.yaml"):  # Numba's name for it, in the working folder
        skipped["yaml"] = "numba.core.config"
    hook = _SkippedByNumba(skipped)
    sys.meta_path.insert(0, hook)
    try:
        import numba  # noqa: F401
    finally:
        with contextlib.suppress(ValueError):
            sys.meta_path.remove(hook)
    record("numba_import_checks_skipped", "scipy" not in hook.skipped)


def set_up_numba() -> None:
    """Make the changes of the module's docstring (once per process)."""
    _import_numba()
    try:
        from numba.core import caching, dispatcher
        from numba.core.runtime import rtsys
    except ImportError:  # a Numba laid out otherwise: as shipped, BLAS check deferred now
        _skipped_loads()
        return
    cache_class = caching.Cache
    dispatcher_class = dispatcher.Dispatcher
    has_parts = (all(hasattr(cache_class, name) for name in (
        "load_overload", "_load_overload", "_guard_against_spurious_io_errors"))
        and hasattr(dispatcher_class, "_compilation_chain_init_hook"))
    if not has_parts:
        _skipped_loads()
        return
    if getattr(cache_class.load_overload, "light_by_mimics", False):  # done already
        return
    full_load = cache_class.load_overload
    init_hook = dispatcher_class._compilation_chain_init_hook

    def load_overload(self: Any, sig: Any, target_context: Any) -> Any:
        if not _is_ours(getattr(self, "_py_func", None)):
            return full_load(self, sig, target_context)
        rtsys.initialize(target_context)  # the runtime that the loaded code calls
        with self._guard_against_spurious_io_errors(), loading_ours():
            return self._load_overload(sig, target_context)
        # None when the guard swallowed an error: Numba compiles, as it would

    def compilation_chain_init_hook(self: Any) -> None:
        if not _is_ours(getattr(self, "py_func", None)):
            init_hook(self)  # a compile of ours loads the entry points at its refresh

    load_overload.light_by_mimics = True  # type: ignore[attr-defined]
    if "numba.np.arraymath" not in sys.modules:
        sys.meta_path.insert(0, _BeforeArraymath())
    cache_class.load_overload = load_overload
    dispatcher_class._compilation_chain_init_hook = compilation_chain_init_hook
    record("light_cache_loads", True)
    record("entry_points_at_compile", True)
    _cache_runtime_library()
    link_modules_when_needed()
    environments_without_imports()


def _skipped_loads() -> None:
    """Numba's cache loads left as shipped; the BLAS probe deferred now."""
    record("light_cache_loads", False)
    record("entry_points_at_compile", False)
    _defer_numba_blas_check()


def _runtime_anchor() -> None:
    """A function of this module: Numba's cache locator says where its kernels go."""


def _cache_runtime_library() -> None:
    try:
        from numba.core import caching
        from numba.core.runtime import nrtdynmod
    except ImportError:
        record("runtime_from_disk", False)
        return
    compile_runtime = getattr(nrtdynmod, "compile_nrt_functions", None)
    make_module = getattr(nrtdynmod, "create_nrt_module", None)
    if compile_runtime is None or make_module is None:
        record("runtime_from_disk", False)
        return

    def cache_file(codegen: Any) -> Path | None:
        """Where the runtime's machine code for ``codegen``'s target is kept."""
        import llvmlite
        import numba

        try:
            folder = Path(caching.FunctionCache(_runtime_anchor)._cache_path)
            key = repr((numba.__version__, llvmlite.__version__, codegen.magic_tuple()))
        except Exception:  # no cache folder Numba could write, or another codegen
            return None
        return folder / f"numba_runtime-{hashlib.sha256(key.encode()).hexdigest()[:16]}.pkl"

    def compile_nrt_functions(ctx: Any) -> Any:
        codegen = ctx.codegen()
        path = cache_file(codegen)
        if path is not None and path.is_file():
            with contextlib.suppress(Exception):  # unreadable: compiled again below
                return codegen.unserialize_library(pickle.loads(path.read_bytes()))
        if path is None:
            return compile_runtime(ctx)
        ir_module, library = make_module(ctx)  # as compile_nrt_functions, its object kept
        library.enable_object_caching()
        library.add_ir_module(ir_module)
        library.finalize()
        with contextlib.suppress(Exception):  # a folder we may not write: nothing kept
            _write_atomically(path, pickle.dumps(library.serialize_using_object_code()))
        return library

    nrtdynmod.compile_nrt_functions = compile_nrt_functions
    record("runtime_from_disk", True)


def _write_atomically(path: Path, data: bytes) -> None:
    """``data`` into ``path`` through a temporary file: a reader sees all of it or none."""
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, name = tempfile.mkstemp(dir=path.parent, prefix=path.name, suffix=".tmp")
    try:
        with os.fdopen(handle, "wb") as file:
            file.write(data)
        os.replace(name, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(name)
        raise
