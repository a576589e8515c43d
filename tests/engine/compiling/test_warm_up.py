"""Compiling ahead (``warm_up``) compiles the very signatures that runs call.

If a part typed an argument otherwise than the engine does, Numba would
compile the kernel again at the run's first call, and the first-run compile
would have been for nothing: each kernel must then hold exactly one signature.
"""

import os
from pathlib import Path

from mimics.algorithms import dispersion, go_to_goal
from mimics.catalog import load_scenario
from mimics.engine.compiling import warm_up
from mimics.engine.simulation import Simulation


def test_each_part_compiles_the_signatures_a_scanning_run_calls():
    Simulation(load_scenario("obstacle_room", robots=12), dispersion, seed=1,
               time_limit=0.3).run()
    Simulation(load_scenario("line", robots=3), go_to_goal, seed=1, time_limit=0.3).run()
    for part in warm_up.PARTS:
        warm_up.compile_part(part)
    for part, kernels in warm_up._WITNESSES.items():
        for kernel in kernels:
            assert len(kernel.signatures) == 1, (part, kernel, kernel.signatures)
    assert warm_up.missing_parts() == []  # every kernel just ran with cache=True


def test_missing_parts_reads_numbas_cache_folders(tmp_path, monkeypatch):
    warm_up.compile_part("motion")
    cache_dir = os.environ.get("NUMBA_CACHE_DIR")
    folder = warm_up._cache_folder(warm_up.move_robots)
    beside = Path(warm_up.move_robots.py_func.__code__.co_filename).parent  # the kernel's module
    expected = Path(cache_dir) if cache_dir else beside / "__pycache__"
    assert expected in (folder, *folder.parents)
    assert any(folder.glob("dynamics.move_robots-*.nbi"))
    monkeypatch.setattr(warm_up, "_cache_folder", lambda kernel: tmp_path)
    assert warm_up.missing_parts() == list(warm_up.PARTS)  # an empty folder: a fresh install


def test_a_scan_waits_for_the_ray_part_compiled_elsewhere():
    waited = []
    warm_up.ray_part_compiling_elsewhere(lambda: waited.append(True))
    Simulation(load_scenario("line", robots=2), go_to_goal, seed=1, time_limit=0.3).run()
    assert waited == []  # no scan read: no wait
    Simulation(load_scenario("obstacle_room", robots=2), dispersion, seed=1,
               time_limit=0.3).run()
    assert waited == [True]
    warm_up.await_ray_part()  # nothing left to wait for
    assert waited == [True]
