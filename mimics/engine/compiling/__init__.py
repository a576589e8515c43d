"""The machinery that compiles and loads the engine's kernels, and Numba's set-up for it.

Importing this package sets Numba up (:func:`set_up_numba`, before Numba itself is
imported) so that a warm run's kernels load from the disk cache with as little of Numba
around them as they need. Its face, for the rest of the engine and the layers above:

* :func:`set_up_numba`, :func:`patch_status` and :data:`PATCHES`: the changes made to
  Numba, why each exists and what it saves (``numba_setup``, ``numba_library_loads``,
  ``patch_record``); the suite fails when one no longer applies to the installed Numba;
* :func:`compile_seconds` and :func:`waiting`: the time this process spent compiling or
  waiting for another process's compile, which no run counts as its own
  (``compile_clock``);
* :func:`heap_frozen`: the objects made before a run kept out of the garbage
  collector's passes during it (``heap_freeze``).

Two modules are imported by name rather than through this face:
``mimics.engine.compiling.warm_up`` (compiling the kernels ahead of a run, in parts that
processes can share) imports the whole engine, so it is loaded only by those who
compile; ``kernel_options`` and ``kernel_minmax`` are building blocks the kernels
themselves import. The CLI's compile processes (``mimics.interfaces.cli.compiling``) run
the warm-up's parts in parallel above this layer.
"""

from mimics.engine.compiling.numba_setup import set_up_numba

set_up_numba()  # before any module below imports Numba

from mimics.engine.compiling.compile_clock import compile_seconds, waiting  # noqa: E402
from mimics.engine.compiling.heap_freeze import heap_frozen  # noqa: E402
from mimics.engine.compiling.patch_record import PATCHES, patch_status  # noqa: E402

__all__ = ["PATCHES", "compile_seconds", "heap_frozen", "patch_status", "set_up_numba",
           "waiting"]
