"""Each change mimics makes to Numba applies to the installed Numba.

Every change is skipped, and Numba behaves as shipped, when Numba's internals are laid
out otherwise (``mimics.engine.compiling``): safe, but a Numba release would then slow
every warm run with no one noticing. These tests fail instead, one per change, so an
upgrade that moves Numba's internals is seen at once (``pyproject.toml`` bounds Numba
above at the newest release this suite has passed on).
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

from mimics.engine.compiling import PATCHES

# a warm run in a fresh process (the first call fills the caches, the second reports)
WARM_RUN = textwrap.dedent("""
    import json, sys
    from mimics.algorithms import wall_aware
    from mimics.catalog import load_scenario
    from mimics.engine.simulation import Simulation
    from mimics.engine.compiling import patch_status

    Simulation(load_scenario("circle_swap", robots=3), wall_aware, seed=1,
               time_limit=0.5).run()
    if sys.argv[1] == "blas":  # what a compile of a kernel using numpy's linalg imports
        import numba.np.arraymath  # noqa: F401
        from numba.np import linalg
        print(json.dumps({"deferred": getattr(linalg.ensure_blas, "deferred_by_mimics", False),
                          "scipy_linalg": "scipy.linalg" in sys.modules}))
    else:
        print(json.dumps({"status": patch_status(),
                          "yaml": "yaml" in sys.modules, "scipy": "scipy" in sys.modules}))
""")


def _warm_run(kind: str) -> dict:
    for _ in range(2):  # the second run loads every kernel from the cache
        done = subprocess.run([sys.executable, "-c", WARM_RUN, kind], capture_output=True,
                              text=True, timeout=600, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def warm() -> dict:
    return _warm_run("status")


@pytest.mark.parametrize("change", [name for name in PATCHES if name != "blas_probe_deferred"])
def test_the_change_applies_to_the_installed_numba(warm: dict, change: str) -> None:
    assert warm["status"][change] is True, (
        f"{change} ({PATCHES[change]}) no longer applies to numba: see "
        "mimics/engine/compiling/numba_setup.py and numba_library_loads.py")


def test_numbas_import_skipped_its_yaml_and_scipy_imports(warm: dict) -> None:
    # what numba_import_checks_skipped saves, seen from outside: neither module imported
    assert not warm["yaml"] and not warm["scipy"]


def test_the_blas_probe_is_deferred_and_scipy_linalg_not_imported() -> None:
    seen = _warm_run("blas")
    assert seen == {"deferred": True, "scipy_linalg": False}


def test_every_change_is_described_with_what_it_saves() -> None:
    assert len(PATCHES) == 8
    for name, saving in PATCHES.items():
        assert any(unit in saving for unit in (" ms", " s")), (name, saving)
