"""Before a battery's local workers start: compile what Numba's cache lacks, once.

On a fresh install (an empty Numba cache) every worker used to compile every
part of the kernels itself, at its warm-up and first runs: the same 15-30 s of
CPU once per worker, on cores the workers share. Instead the battery process
asks :func:`mimics.engine.compiling.warm_up.missing_parts` and, if some part is missing,
compiles each in a short-lived process of its own, all at once, and waits for
them; the workers then load every part from the cache at their warm-up.

A compile process comes from the workers' own context (:func:`worker_context`):
under ``forkserver`` it is forked from the fork server, which has the engine
imported but has run nothing (the workers' rule, :mod:`mimics.batteries.preload`),
so it compiles at once, and the fork server is then ready for the workers. The
battery process itself only reads the cache's folder: it compiles and runs no
kernel. A compile process that fails or outlasts :data:`COMPILE_LIMIT` loses
nothing: the workers compile what is still missing, as they did before.

Dask workers are not covered: each starts its own worker processes on its
machine (:mod:`mimics.batteries.dask_backend`), which compile at their first runs.
"""

from __future__ import annotations

import multiprocessing
import signal
import sys
import time
from pathlib import Path

from mimics.batteries.workers import (
    STARTUP_LIMIT,
    _die_with_parent_signal,
    _redirect_output,
    worker_context,
)

#: Seconds the battery waits for its compile processes before the workers start anyway.
COMPILE_LIMIT = STARTUP_LIMIT
#: The battery's line when it compiles (the CLI's first run says the same of a run).
MESSAGE = ("mimics: first battery on this install: compiling the simulation kernels once "
           "for all workers (they are cached on disk for the next runs)")


def compile_missing_parts(log_dir: Path | None, limit: float = COMPILE_LIMIT) -> list[str]:
    """Compile the parts Numba's cache lacks, one process per part, and wait for them.

    Args:
        log_dir: where each compile process writes ``compile-PART.log`` (None: its
            output goes where this process's goes).
        limit: seconds to wait before the remaining compile processes are killed.

    Returns:
        The parts whose process ended well (empty when the cache had everything).
    """
    from mimics.engine.compiling.warm_up import missing_parts

    missing = missing_parts()
    if not missing:
        return []
    print(MESSAGE, file=sys.stderr, flush=True)
    if log_dir is not None:
        log_dir.mkdir(parents=True, exist_ok=True)
    context = worker_context(warm_up=True)  # the engine preloaded in the fork server
    processes: dict[str, multiprocessing.process.BaseProcess] = {}
    try:
        for part in missing:
            log = str((log_dir / f"compile-{part}.log").resolve()) if log_dir else ""
            process = context.Process(target=_compile_part, args=(part, log),
                                      name=f"mimics-{part}", daemon=True)
            process.start()
            processes[part] = process
        deadline = time.monotonic() + limit
        for process in processes.values():
            process.join(max(0.0, deadline - time.monotonic()))
    except Exception:  # only a speed-up: the workers compile what is missing
        pass
    finally:
        for process in processes.values():
            if process.is_alive():
                process.kill()
                process.join(1.0)
    return [part for part, process in processes.items() if process.exitcode == 0]


def _compile_part(part: str, log_path: str) -> None:
    """A compile process's whole life: compile ``part`` into Numba's cache."""
    _die_with_parent_signal()  # the fork server ends with the battery: so does this
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the battery's: it kills us
    if log_path:
        _redirect_output(log_path)
    from mimics.engine.compiling.warm_up import compile_part

    compile_part(part)
