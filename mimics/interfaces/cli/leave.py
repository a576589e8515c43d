"""Ending the ``mimics`` process once its command is done, without Python's teardown.

After a command that ran a simulation, the interpreter's own shutdown spends
about 0.25 s releasing, one by one, the LLVM objects of the compiled kernels
that Numba loaded: 0.3 s of the README command's 2.6 s (measured: the same
command ended with ``os._exit`` after its exit handlers). By then every file
the command wrote is closed. So the console script runs the exit handlers
(``atexit``: multiprocessing's children, logging, Dask's clients, ROS masters
and nodes), flushes the standard streams and ends the process. A command that
leaves a thread of its own running ends the ordinary way, which waits for it.
"""

from __future__ import annotations

import atexit
import contextlib
import os
import sys
import threading
from typing import NoReturn


def leave(code: int) -> NoReturn:
    """End the process with status ``code`` (see the module's docstring)."""
    others = [thread for thread in threading.enumerate()
              if thread is not threading.main_thread() and not thread.daemon]
    if others:  # Python's shutdown waits for them; os._exit would cut them off
        sys.exit(code)
    atexit._run_exitfuncs()
    for stream in (sys.stdout, sys.stderr):
        # a closed pipe (`mimics ... | head`) or stream: nothing more can be said there
        with contextlib.suppress(OSError, ValueError):
            stream.flush()
    os._exit(code)


def console() -> NoReturn:
    """The ``mimics`` console script and ``python -m mimics``: :func:`main`, then :func:`leave`."""
    from mimics.interfaces.cli.program import main

    leave(main())
