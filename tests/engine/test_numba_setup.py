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

    from mimics.engine import numba_setup

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
