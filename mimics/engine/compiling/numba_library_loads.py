"""How a cached kernel of mimics loads with less of Numba around it
(``numba_setup.set_up_numba`` installs this; each change is skipped, and
Numba behaves as shipped, when its internals are laid out otherwise):

* **A library loaded from the cache reads its symbols from its machine code.**
  Numba keeps each cached kernel's LLVM module beside its machine code, for a
  later compile to link in, and parses it at every load to list the names the
  library defines (1.5 to 2.5 ms a kernel, a third of a warm Cave run's
  loads). The names are read from the ELF object's symbol table instead (the
  same set: tested) and the module is parsed when a compile first links it.
  Other object formats load as Numba ships.

* **Numba's implementations are not imported to load a kernel that inlined them.**
  A cached kernel names the environment of each of Numba's implementations it
  inlined (``np.empty``'s, ``math.hypot``'s), and Numba imports each one's
  module to rebuild it: ``numba.np.arrayobj`` alone pulls in Numba's strings,
  hashing and random number modules, 50 ms of every warm run. Such an
  environment, when it holds no constants, is rebuilt without its module:
  nopython code reads only an environment's constants (its module's globals
  serve object mode, which none of them is compiled in).

* **No lock events.** While one of mimics' own kernels loads, Numba's
  bookkeeping around each call into LLVM (an event per lock, for compile
  statistics) is off: about 3,500 calls of a warm Cave run, 10 ms.

The kernels' machine code and results are those Numba would load.
"""

from __future__ import annotations

import contextlib
import struct
import sys
import weakref
from collections.abc import Iterator
from typing import Any

from mimics.engine.compiling.patch_record import record

# while one of mimics' kernels loads: how the environments it names are rebuilt
_light_env: list[Any] = []


@contextlib.contextmanager
def loading_ours() -> Iterator[None]:
    """The block loads one of mimics' kernels: no lock events, and Numba's
    ``_rebuild_env`` swapped for the light one of :func:`environments_without_imports`
    (during the block only: a compile's cache files must name Numba's own function, as
    each cached environment is pickled with it)."""
    environment = sys.modules.get("numba.core.environment")
    full = getattr(environment, "_rebuild_env", None)
    if _light_env and full is not None:
        environment._rebuild_env = _light_env[0]  # type: ignore[union-attr]
    try:
        with _quiet_llvm_lock():
            yield
    finally:
        if full is not None:
            environment._rebuild_env = full  # type: ignore[union-attr]


@contextlib.contextmanager
def _quiet_llvm_lock() -> Iterator[None]:
    """Numba's callbacks on each call into LLVM (events for its compile statistics) off
    for the block: a cache load makes thousands of calls and records no statistics."""
    ffi = sys.modules.get("llvmlite.binding.ffi")
    lock = getattr(getattr(ffi, "lib", None), "_lock", None)
    if not isinstance(getattr(lock, "_cblist", None), list):  # laid out otherwise: as shipped
        record("no_lock_events", False)
        yield
        return
    record("no_lock_events", True)
    saved, lock._cblist = lock._cblist, []  # type: ignore[union-attr]
    try:
        yield
    finally:
        lock._cblist = saved  # type: ignore[union-attr]


def link_modules_when_needed() -> None:
    """A library loaded from the cache reads its symbols from its machine code; its LLVM
    module (kept for a later compile to link in) is parsed only when one does."""
    try:
        import llvmlite.binding as ll
        from numba.core.codegen import CPUCodeLibrary
    except ImportError:
        record("symbols_from_machine_code", False)
        return
    full_unserialize = CPUCodeLibrary.__dict__.get("_unserialize")
    full_linking_module = CPUCodeLibrary.__dict__.get("_get_module_for_linking")
    if not isinstance(full_unserialize, classmethod) or full_linking_module is None \
            or getattr(full_linking_module, "light_by_mimics", False):
        record("symbols_from_machine_code",
               getattr(full_linking_module, "light_by_mimics", False))
        return
    needed = ("create_library", "_engine")

    def unserialize(cls: Any, codegen: Any, state: Any) -> Any:
        name, kind, data = state
        # no names read (another format, or none found): Numba's own load
        symbols = defined_symbols(data[0]) if kind == "object" else None
        engine = getattr(codegen, "_engine", None)
        if not symbols or not isinstance(getattr(engine, "_defined_symbols", None), set) \
                or not all(hasattr(codegen, part) for part in needed):
            return full_unserialize.__func__(cls, codegen, state)
        object_code, shared_bitcode = data
        library = codegen.create_library(name)
        library.enable_object_caching()
        library._set_compiled_object(object_code)
        library._linking_bitcode_by_mimics = shared_bitcode
        library._finalize_final_module()
        engine._defined_symbols |= symbols  # what Numba reads from the parsed module
        return library

    def get_module_for_linking(self: Any) -> Any:
        bitcode = self.__dict__.pop("_linking_bitcode_by_mimics", None)
        if bitcode is not None:
            self._shared_module = ll.parse_bitcode(bitcode)
        return full_linking_module(self)

    get_module_for_linking.light_by_mimics = True  # type: ignore[attr-defined]
    CPUCodeLibrary._unserialize = classmethod(unserialize)  # type: ignore[assignment]
    CPUCodeLibrary._get_module_for_linking = get_module_for_linking  # type: ignore[method-assign]
    record("symbols_from_machine_code", True)


def defined_symbols(object_code: bytes) -> set[str] | None:
    """The names an ELF64 little-endian object file defines (its symbol table's entries
    in a section, files and sections aside), or None for any other object format."""
    if object_code[:6] != b"\x7fELF\x02\x01":
        return None
    try:
        (section_table,) = struct.unpack_from("<Q", object_code, 0x28)
        entry_size, count = struct.unpack_from("<HH", object_code, 0x3A)
        sections = [struct.unpack_from("<IIQQQQIIQQ", object_code, section_table + i * entry_size)
                    for i in range(count)]
        names: set[str] = set()
        for _, kind, _, _, offset, size, link, _, _, symbol_size in sections:
            if kind != 2 or symbol_size <= 0:  # SHT_SYMTAB
                continue
            strings = sections[link][4]
            for start in range(offset, offset + size, symbol_size):
                name, info, _, section, _, _ = struct.unpack_from("<IBBHQQ", object_code, start)
                # defined (in a section) and named; not a file or section symbol
                if name and section != 0 and (info & 0xF) not in (3, 4):
                    end = object_code.index(b"\0", strings + name)
                    names.add(object_code[strings + name:end].decode())
        return names
    except (struct.error, ValueError, IndexError, UnicodeDecodeError):
        return None


def environments_without_imports() -> None:
    """While a kernel of mimics loads, the environment of an implementation of Numba's own
    that holds no constants is made without importing its module (see the docstring)."""
    try:
        from numba.core import environment
    except ImportError:
        record("environments_without_imports", False)
        return
    full_rebuild = getattr(environment, "_rebuild_env", None)
    make = getattr(environment, "Environment", None)
    if full_rebuild is None or make is None or _light_env \
            or not isinstance(getattr(make, "_memo", None), weakref.WeakValueDictionary):
        record("environments_without_imports", bool(_light_env))
        return

    def rebuild_env(module: str, consts: Any, name: str) -> Any:
        if consts or not str(module).startswith("numba.") or module in sys.modules \
                or environment.lookup_environment(name) is not None:
            return full_rebuild(module, consts, name)
        # nopython code reads only an environment's constants; its globals serve object
        # mode, which none of Numba's implementations is compiled in
        env = make({"__name__": module})
        env.env_name = name
        make._memo[name] = env
        return env

    _light_env[:] = [rebuild_env]
    record("environments_without_imports", True)
