"""An audit hook that stops user code from reaching the simulation by ``gc`` or frames.

The views a step gets hold no reference to the simulation (``robot_view``), but
in one Python process every object can be reached by walking the garbage
collector's lists (``gc.get_objects``, ``gc.get_referrers``) or the call stack
(``sys._getframe().f_back``, a traceback's ``tb_frame``, a generator's
``gi_frame``), or by ``ctypes`` and tracing hooks. :func:`install_guard`
(battery workers call it) makes these raise ``PermissionError`` when the code
asking is the user's: the first caller outside Python's own library is a file
of the user's (:func:`mimics.engine.user_code.failure_places.is_user_file`). mimics' own code
and installed packages (NumPy, Numba) are not affected, and neither are
``warnings`` and ``logging``, which read frames for their own use.

This is a speed bump, not a sandbox: an audit hook cannot see every way in (a
C extension the student brings, ``/proc/self/mem``). The boundary is the worker
process (each submission's runs see only themselves) and, where the system has
it, the OS sandbox of docs/explanation/containment.md.
"""

from __future__ import annotations

import sys
import sysconfig
from pathlib import Path
from typing import Any

from mimics.engine.user_code.failure_places import is_user_file

#: Events refused to user code (``ctypes.*`` too).
BLOCKED = frozenset({"gc.get_objects", "gc.get_referrers", "gc.get_referents",
                     "sys._getframe", "sys._current_frames", "sys.settrace", "sys.setprofile",
                     "sys._current_exceptions"})
#: Attributes that hand out frames (the ``object.__getattr__`` event).
FRAME_ATTRIBUTES = frozenset({"tb_frame", "gi_frame", "cr_frame", "ag_frame"})
#: Standard modules that read frames for themselves and hand none out.
FRAME_READERS = ("warnings", "logging")

_STDLIB = str(Path(sysconfig.get_paths()["stdlib"]).resolve())
_installed = False


def install_guard() -> None:
    """Install the hook in this process (once; an audit hook cannot be removed)."""
    global _installed
    if _installed:
        return
    _installed = True
    busy = [False]  # the hook's own frame reads raise the event again: let those through

    def guard(event: str, args: tuple[Any, ...]) -> None:
        if busy[0]:
            return
        if event == "object.__getattr__":
            if len(args) < 2 or args[1] not in FRAME_ATTRIBUTES:
                return
        elif event not in BLOCKED and not event.startswith("ctypes."):
            return
        busy[0] = True
        try:
            refused = _asked_by_user(event)
        finally:
            busy[0] = False
        if refused:
            raise PermissionError(f"{event} is not available to algorithms in a battery "
                                  "(it could reach the simulation's state)")

    sys.addaudithook(guard)  # held by the interpreter alone: user code cannot reach it


def _asked_by_user(event: str) -> bool:
    """Whether the first caller outside the standard library is user code."""
    frame = sys._getframe(2)  # past _asked_by_user and guard: the code that raised the event
    first = True
    while frame is not None:
        filename = frame.f_code.co_filename
        in_stdlib = filename.startswith(_STDLIB) or filename.startswith("<frozen")
        if not in_stdlib:
            return is_user_file(filename)
        module = frame.f_globals.get("__name__", "")
        if first and (module in FRAME_READERS or (module == "traceback"
                                                  and frame.f_code.co_name.startswith("_"))):
            return False  # reads frames for its own use (a warning's place, a traceback)
        first = False
        frame = frame.f_back
    return False
