"""How ``mimics.engine`` sets Numba up: its own cached kernels load without refreshing
Numba's registries, with the same results; everything else behaves as Numba ships it.

Each check runs in fresh processes (what a warm ``mimics run`` is): the first
one may compile and fill the caches, the second loads from them.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np

from mimics.algorithms import go_to_goal
from mimics.catalog import load_scenario
from mimics.engine.simulation import Simulation

SCRIPT = textwrap.dedent("""
    import json, sys
    import numpy as np
    from mimics.algorithms import go_to_goal
    from mimics.catalog import load_scenario
    from mimics.engine.simulation import Simulation

    result = Simulation(load_scenario("line", robots=3), go_to_goal, seed=4,
                        time_limit=0.5).run()
    after_run = {name: name in sys.modules for name in
                 ("numba.np.arraymath", "scipy.linalg", "cffi")}
    import numba.np.arraymath  # as a cached kernel's environment may import it

    blas_probed = "scipy.linalg" in sys.modules
    import user_kernel  # a kernel of another package, cached on disk

    plus_one = user_kernel.plus_one(np.arange(3.0)).tolist()
    after_user_kernel = "numba.np.arraymath" in sys.modules
    from numba import njit

    @njit
    def dot(a, b):  # compiled now, after the loads: needs the registries and BLAS
        return np.dot(a, b)

    @njit
    def doubled(a):  # allocates an array: Numba's runtime, loaded from the disk
        return a * 2

    print(json.dumps({"digest": result.trajectory_digest, "after_run": after_run,
                      "blas_probed": blas_probed, "plus_one": plus_one,
                      "after_user_kernel": after_user_kernel,
                      "dot": dot(np.arange(4.0), np.arange(4.0) + 1),
                      "doubled": doubled(np.arange(3.0)).tolist()}))
""")

USER_KERNEL = textwrap.dedent("""
    from numba import njit

    @njit(cache=True)
    def plus_one(x):
        return x + 1
""")


def runtime_cache_folder() -> Path:
    from numba.core.caching import FunctionCache

    from mimics.engine.compiling import numba_setup

    return Path(FunctionCache(numba_setup._runtime_anchor)._cache_path)


def run_fresh(folder: Path) -> dict[str, object]:
    done = subprocess.run([sys.executable, "-c", SCRIPT], cwd=folder, capture_output=True,
                          text=True, check=True, env=None)
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_cached_kernels_load_without_refreshing_numba_and_others_as_shipped(tmp_path):
    (tmp_path / "user_kernel.py").write_text(USER_KERNEL)
    run_fresh(tmp_path)  # fills the caches (the engine's usually are already)
    loaded = run_fresh(tmp_path)
    # the engine's kernels came from the cache without Numba's refresh and BLAS probe
    assert loaded["after_run"] == {"numba.np.arraymath": False, "scipy.linalg": False,
                                   "cffi": False}
    # the same trajectory as a run in this process (whatever its kernels' origin)
    here = Simulation(load_scenario("line", robots=3), go_to_goal, seed=4,
                      time_limit=0.5).run()
    assert loaded["digest"] == here.trajectory_digest
    # importing numba.np.arraymath does not probe BLAS through SciPy
    assert loaded["blas_probed"] is False
    # another package's cached kernel loads as Numba ships it: with the refresh
    assert loaded["plus_one"] == [1.0, 2.0, 3.0]
    assert loaded["after_user_kernel"] is True
    # and a compile after all that works, BLAS included
    assert loaded["dot"] == float(np.dot(np.arange(4.0), np.arange(4.0) + 1))
    assert loaded["doubled"] == [0.0, 2.0, 4.0]
    # the runtime's machine code was kept beside the engine's kernels, and loaded
    assert list(runtime_cache_folder().glob("numba_runtime-*.pkl"))
    # a kernel cached by a process that loaded the engine's kernels names only Numba's
    # own functions (none of mimics' stand-ins is pickled into another cache)
    (cached,) = (tmp_path / "__pycache__").glob("user_kernel.plus_one-*.nbc")
    assert b"mimics" not in cached.read_bytes()


IMPORTS = textwrap.dedent("""
    import json, sys
    import mimics.engine  # imports Numba, as every run does
    from mimics.engine.compiling import warm_up

    before = {name: name in sys.modules for name in ("scipy", "yaml")}
    warm_up.compile_index_kernels()  # loads (or compiles) kernels of mimics
    warm_up.compile_motion_kernels()
    warm_up.compile_ray_kernel()
    arrays_imported = "numba.np.arrayobj" in sys.modules  # np.empty's implementation
    import numpy as np
    import numba

    @numba.njit
    def twos(n):  # compiled now: inlines np.empty's implementation, whose environment
        out = np.empty(n)  # the loads made without its module
        out[:] = 2.0
        return out

    twos_made = twos(3).tolist()
    import llvmlite.binding.ffi as ffi
    import scipy, yaml  # what Numba skipped imports as usual afterwards

    print(json.dumps({"before": before, "developer_mode": numba.config.DEVELOPER_MODE,
                      "arrays_imported": arrays_imported, "twos": twos_made,
                      "lock_callbacks": len(ffi.lib._lock._cblist),
                      "scipy": scipy.__version__.count(".") >= 1, "yaml": yaml.safe_load("a: 1")}))
""")


def run_imports(folder: Path) -> dict[str, object]:
    done = subprocess.run([sys.executable, "-c", IMPORTS], cwd=folder, capture_output=True,
                          text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def test_numba_is_imported_without_its_scipy_check_and_yaml_unless_a_config_file_is_there(
        tmp_path):
    run_imports(tmp_path)  # compiles what the caches lack (a fresh checkout's first run)
    plain = run_imports(tmp_path)
    assert plain["before"] == {"scipy": False, "yaml": False}
    assert plain["scipy"] is True and plain["yaml"] == {"a": 1}
    # a warm load of the kernels imports none of Numba's implementations they inlined,
    # and a compile afterwards that inlines one of them runs as it should
    assert plain["arrays_imported"] is False
    assert plain["twos"] == [2.0, 2.0, 2.0]
    # Numba's own callbacks around LLVM calls are back after the kernels' loads
    assert plain["lock_callbacks"] >= 1
    # a Numba config file in the working folder is read, as Numba documents (PyYAML kept)
    (tmp_path / ".numba_config.yaml").write_text("developer_mode: 1\n")
    configured = run_imports(tmp_path)
    assert configured["before"]["yaml"] is True
    assert configured["developer_mode"] == 1


LINKING = textwrap.dedent("""
    import json
    import llvmlite.binding as ll
    from numba import njit
    from mimics.engine.compiling import numba_library_loads, warm_up
    from mimics.engine.spatial_index import grid_frame
    from numba.core.codegen import CPUCodeLibrary

    objects = {}  # each library's machine code, as it is set (a load consumes it)
    set_object = CPUCodeLibrary._set_compiled_object

    def keep_object(library, value):
        objects[id(library)] = value
        set_object(library, value)

    CPUCodeLibrary._set_compiled_object = keep_object
    warm_up.compile_index_kernels()  # grid_frame among them, from the cache
    warm_up.compile_motion_kernels()
    libraries = [overload.library for kernel in warm_up._WITNESSES["index"]
                 + warm_up._WITNESSES["motion"] + (grid_frame,)
                 for overload in kernel.overloads.values()]
    engine = libraries[0]._codegen._engine
    checked = []
    for library in libraries:
        bitcode = getattr(library, "_linking_bitcode_by_mimics", None)
        if bitcode is None:
            continue
        module = ll.parse_bitcode(bitcode)  # what Numba would have parsed at the load
        numba_names = {value.name for values in (module.functions, module.global_variables)
                       for value in values if not value.is_declaration}
        from_object = numba_library_loads.defined_symbols(objects[id(library)])
        checked.append(from_object == numba_names and numba_names <= engine._defined_symbols)

    @njit
    def cells_of_a_box(x):  # a new compile that links the loaded grid_frame in
        origin, shape, cell = grid_frame(0.0, 0.0, x, 2.0, 0.5)
        return shape[0] * shape[1]

    print(json.dumps({"checked": checked, "cells": int(cells_of_a_box(3.0)),
                      "direct": [int(n) for n in grid_frame(0.0, 0.0, 3.0, 2.0, 0.5)[1]]}))
""")


def test_a_cached_kernel_loads_its_symbols_from_its_machine_code_and_links_later(tmp_path):
    (tmp_path / "user_kernel.py").write_text(USER_KERNEL)
    run_fresh(tmp_path)  # the engine's caches filled
    done = subprocess.run([sys.executable, "-c", LINKING], cwd=tmp_path, capture_output=True,
                          text=True, check=True)
    seen = json.loads(done.stdout.strip().splitlines()[-1])
    # every library loaded from the cache defines, by its object file's symbol table, the
    # names Numba reads from its LLVM module, and the execution engine knows them all
    assert len(seen["checked"]) >= 5 and all(seen["checked"])
    # a kernel compiled afterwards links a loaded one (its module parsed then) and runs
    assert seen["direct"] == [6, 4]
    assert seen["cells"] == 24


def test_defined_symbols_reads_only_elf64_little_endian_objects():
    from mimics.engine.compiling.numba_library_loads import defined_symbols

    assert defined_symbols(b"\xcf\xfa\xed\xfe" + bytes(60)) is None  # Mach-O
    assert defined_symbols(b"\x7fELF\x02\x01" + bytes(10)) is None  # cut short
