"""The objects made before a run, left out of the garbage collector's passes during it.

A process that runs a simulation holds tens of thousands of objects made before
the run (its imports, the compiled kernels Numba loaded, the scenario), none of
which the run frees. Python's full collections walk them all: one such pass
came in the middle of a Hospital run, 50 to 90 ms (2,000 robots, 10 s). Frozen
(:func:`gc.freeze`) for the run (``Simulation.run``) and for the set-up
(``mimics.records.runner.prepare``: one such pass while 100,000 robots were
built, 26-37 ms, 2-3 ms frozen), they are skipped; the collections of what the
run makes go on as before. They are handed back (:func:`gc.unfreeze`) when the
run ends, so garbage made before it is collected afterwards as it would have
been, and nothing stays frozen for good. A process that froze its own objects
(``gc.get_freeze_count()``, a forking server say) is left as it is.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager


@contextmanager
def heap_frozen() -> Iterator[None]:
    """Freeze the collector's tracked objects for the ``with`` block, then unfreeze them."""
    if gc.get_freeze_count() or not gc.isenabled():
        yield
        return
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()
