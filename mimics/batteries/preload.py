"""Preloaded by the fork server of battery workers: the engine's imports.

The fork server imports this module once (:func:`mimics.batteries.workers.worker_context`),
so that every worker forked from it starts with numpy, Numba, Arrow and the
engine imported. Nothing runs here: a compiled kernel run in the fork server
would start Numba's OpenMP thread pool, and forking a process that has one is
unsafe; each worker loads the compiled kernels itself with a tiny run, and
on a fresh install the kernels are compiled in forks of the fork server, one
per part (:mod:`mimics.batteries.compile_once`).
"""

import mimics.engine.simulation
import mimics.records.runner  # noqa: F401
