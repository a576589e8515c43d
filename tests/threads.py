"""How many threads the engine splits its kernels over, set for a test."""

from collections.abc import Iterator
from contextlib import contextmanager
from unittest import mock

from mimics.engine.helper_threads import threads as kernel_threads


@contextmanager
def thread_count(threads: int) -> Iterator[None]:
    """The engine's kernels take helpers as if Numba had ``threads`` threads. Helper
    threads need no second core, so the tests of 1 against 2 threads run everywhere,
    a one-core machine included (``numba.set_num_threads`` cannot go above the
    machine's count there)."""
    with mock.patch.object(kernel_threads, "get_num_threads", lambda: threads):
        yield
