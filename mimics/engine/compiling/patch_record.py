"""Which of the changes to Numba (``numba_setup``, ``numba_library_loads``) took effect in
this process: each change is skipped, and Numba behaves as shipped, when Numba's
internals are laid out otherwise, so that a Numba release changing them slows runs
quietly. The suite reads :func:`patch_status` (``tests/engine/test_numba_patches.py``)
and fails on the first Numba a change no longer applies to."""

from __future__ import annotations

# what each change saves, measured on the project's 2-core machine (warm runs; see the
# docstrings of numba_setup and numba_library_loads)
PATCHES: dict[str, str] = {
    "light_cache_loads": "a cached kernel of mimics loads without refreshing Numba's "
                         "registries: 0.2-0.3 s of CPU a warm run",
    "entry_points_at_compile": "numba_extensions entry points scanned only by a compile: "
                               "20-30 ms",
    "blas_probe_deferred": "no scipy.linalg import for kernels that use no BLAS: "
                           "0.15-0.4 s",
    "numba_import_checks_skipped": "Numba's SciPy version check and PyYAML import skipped: "
                                   "10-40 ms",
    "runtime_from_disk": "Numba's runtime (NRT) loaded, not compiled: 40-50 ms a process",
    "symbols_from_machine_code": "a cached library's names read from its ELF symbol table: "
                                 "1.5-2.5 ms a kernel",
    "environments_without_imports": "Numba's implementations' modules not imported to load "
                                    "a kernel: about 50 ms",
    "no_lock_events": "no LLVM lock events while a kernel loads: about 10 ms a Cave run",
}

_status: dict[str, bool] = {}


def record(name: str, applied: bool) -> None:
    """Note whether change ``name`` (a key of :data:`PATCHES`) took effect."""
    if name not in PATCHES:
        raise KeyError(f"unknown Numba change {name!r}")
    _status[name] = _status.get(name, False) or applied


def patch_status() -> dict[str, bool | None]:
    """Every change: True (applied), False (skipped: Numba laid out otherwise) or None
    (not reached yet in this process, e.g. no kernel loaded from the cache)."""
    return {name: _status.get(name) for name in PATCHES}
