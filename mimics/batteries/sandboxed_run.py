"""``python -m mimics.batteries.sandboxed_run FD THREADS LABEL``: one battery run in a sandbox.

Started by :mod:`mimics.batteries.sandbox` under bubblewrap. It talks over the
socket ``FD`` as a battery worker does (:func:`mimics.batteries.workers.worker_main`):
says it is ready, receives one task, sends back its outcome, and ends. Its output
goes to the worker log the battery opened for it.

The file system is read-only in the sandbox, Numba's cache of the engine's
kernels included. Numba refuses a cache folder it cannot write (and then refuses
to define the kernel at all), so here a cache folder that exists is taken as it
is: kernels load from it, and one it lacks is compiled in memory and not saved
(the battery compiles what the cache lacks before any run starts:
:mod:`mimics.batteries.compile_once`). A run cannot change the cache other runs load.
"""

from __future__ import annotations

import contextlib
import os
import sys
from typing import Any


def read_only_numba_cache() -> None:
    """Let Numba load kernels from cache folders it cannot write, and skip saving there."""
    from numba.core import caching

    ensure = caching._CacheLocator.ensure_cache_path

    def ensure_readable(self: Any) -> None:
        try:
            ensure(self)
        except OSError:
            if not os.path.isdir(self.get_cache_path()):
                raise

    save = caching.Cache.save_overload

    def save_if_possible(self: Any, sig: Any, data: Any) -> None:
        with contextlib.suppress(OSError):
            save(self, sig, data)

    caching._CacheLocator.ensure_cache_path = ensure_readable  # type: ignore[method-assign]
    caching.Cache.save_overload = save_if_possible  # type: ignore[method-assign]


def main(argv: list[str]) -> int:
    """Run one task received over the socket ``argv[0]``."""
    from multiprocessing.connection import Connection

    fd, threads, label = int(argv[0]), int(argv[1]), argv[2]
    read_only_numba_cache()
    from mimics.batteries.workers import worker_main

    parent = os.getppid()  # bwrap's: the battery is not visible from the PID namespace
    worker_main(Connection(fd), parent, "", death_signal=False, warm_up=True,
                threads=threads, one_task=True, label=label)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
