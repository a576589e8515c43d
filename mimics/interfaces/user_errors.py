"""``mimics.UserCodeError``: the user's algorithm failed, raised where a Python user looks.

``mimics.simulate`` records a run whose algorithm raised (status ``error``)
and then raises :class:`UserCodeError` with the run attached (``.run``). The
algorithm's own exception is its cause, its traceback cut to the user's frames,
so that IPython shows the cell and line of the bug (``Cell In[3], line 4``) and a
script the file and line. In a notebook, the places in the message read as
IPython names them (``Cell In[3], line 4``) rather than ipykernel's temporary
files.

>>> error = UserCodeError("ZeroDivisionError in robot 0 at t=0 s: division by zero", run=None)
>>> str(error), error.run is None
('ZeroDivisionError in robot 0 at t=0 s: division by zero', True)
"""

from __future__ import annotations

import re
from types import TracebackType
from typing import Any

from mimics.engine.user_code import is_user_file

#: ``file.py:LINE`` in an error text (a path without spaces, then its line).
_PLACE = re.compile(r"(?P<file>[^\s,:()'\"]+\.py):(?P<line>\d+)")


class UserCodeError(Exception):
    """The user's algorithm raised or returned something invalid; the run ended ``error``.

    Attributes:
        run: the recorded run (a :class:`~mimics.interfaces.notebook.run.RunView`), up to
            the failure.
    """

    def __init__(self, message: str, run: Any) -> None:
        super().__init__(message)
        self.run = run


def user_frames(tb: TracebackType | None) -> TracebackType | None:
    """The traceback from the first frame of user code on (``tb`` itself when none is)."""
    current = tb
    while current is not None:
        if is_user_file(current.tb_frame.f_code.co_filename):
            return current
        current = current.tb_next
    return tb


def cell_places(text: str) -> str:
    """``text`` with ipykernel's temporary files named as IPython names them
    (``/tmp/ipykernel_12/345.py:4`` -> ``Cell In[3], line 4``); as is outside a kernel."""
    namer = _code_namer()
    if namer is None:
        return text

    def named(match: re.Match[str]) -> str:
        try:
            label = namer(match["file"])
        except Exception:  # IPython's private naming may change: keep the path
            label = None
        if not label:
            return match[0]
        kind, name = label
        return f"{kind} {name}, line {match['line']}"

    return _PLACE.sub(named, text)


def _code_namer() -> Any:
    """IPython's ``compile.format_code_name`` (file -> ("Cell", "In[3]")), or None."""
    import sys

    if "IPython" not in sys.modules:
        return None
    from IPython import get_ipython

    shell = get_ipython()
    compiler = getattr(shell, "compile", None)
    return getattr(compiler, "format_code_name", None)


def user_code_error(run: Any, exception: BaseException | None) -> UserCodeError:
    """The :class:`UserCodeError` of ``run`` (status ``error``), caused by the algorithm's
    ``exception`` (its traceback cut to the user's frames) when there is one."""
    message = cell_places(str(run.summary.get("error") or "the algorithm failed"))
    error = UserCodeError(message, run)
    if exception is not None:
        exception.__traceback__ = user_frames(exception.__traceback__)
        error.__cause__ = exception  # as ``raise ... from exception``
    return error
