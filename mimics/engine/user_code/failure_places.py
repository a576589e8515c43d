"""Where in the user's code a failure happened: the file, the line and its text.

A failure of user code is reported as pytest's short tracebacks report a
test (``--tb=short``): the file and line in the user's code, the source line,
the exception's one-line message, and a traceback cut to the user's frames.
mimics' own frames (the engine calling the step), the standard library's and
installed packages' are left out; the built-in algorithms (``mimics/algorithms``)
count as user code, as examples a user copies.

An invalid output (one number, ``None``, NaN) raises nothing, so it has no
traceback: :func:`return_lines` finds the ``return`` statements of the step
function that can have produced it, from the function's source, only once a
failure was seen (nothing is traced on the normal path).
"""

from __future__ import annotations

import ast
import functools
import inspect
import linecache
import math
import os
import sys
import sysconfig
import textwrap
import traceback
from dataclasses import dataclass
from pathlib import Path
from types import CodeType, FunctionType, TracebackType
from typing import Any

_MIMICS = Path(__file__).resolve().parents[2]  # the mimics package
_USER_PARTS = (str(_MIMICS / "algorithms") + os.sep,)
# Python's library, installed packages (also Debian's dist-packages, where ROS's are) and mimics
_NOT_USER = tuple(sorted({str(Path(p).resolve()) + os.sep for p in (
    sysconfig.get_paths()["stdlib"], sysconfig.get_paths()["purelib"],
    sysconfig.get_paths()["platlib"],
    *(p for p in sys.path if Path(p).name in ("site-packages", "dist-packages")))}
    | {str(_MIMICS) + os.sep}))


@dataclass(frozen=True)
class Place:
    """A line of user code: ``file:line`` and the line's text (stripped; "" if unknown)."""

    file: str
    line: int
    text: str = ""

    def __str__(self) -> str:
        return f"{shown_path(self.file)}:{self.line}"


def is_user_file(filename: str) -> bool:
    """Whether frames of ``filename`` are the user's (not mimics', Python's or a package's)."""
    if filename.startswith("<"):  # <frozen ...>: Python's own; <stdin>, <string>: the user's
        return not filename.startswith("<frozen")
    path = os.path.abspath(filename)
    if path.startswith(_USER_PARTS):
        return True
    if any(f"{os.sep}{name}{os.sep}" in path for name in ("site-packages", "dist-packages")):
        return False  # a package, also one whose folder joined sys.path later (ROS's rospy)
    return not path.startswith(_NOT_USER)


def shown_path(filename: str) -> str:
    """``filename`` relative to the working folder when it is inside it, else as given."""
    try:
        relative = os.path.relpath(filename)
    except ValueError:  # another drive (Windows)
        return filename
    return filename if relative.startswith("..") else relative


def source_line(filename: str, line: int) -> str:
    """The text of ``line`` in ``filename``, stripped ("" when it cannot be read)."""
    return linecache.getline(filename, line).strip()


def _user_entries(tb: TracebackType | None) -> list[traceback.FrameSummary]:
    frames = traceback.extract_tb(tb)
    return [f for f in frames if is_user_file(f.filename)]


def failure_place(exc: BaseException) -> Place | None:
    """The innermost line of user code in ``exc``'s traceback (None: none of it is the user's)."""
    entries = _user_entries(exc.__traceback__)
    if not entries:
        return None
    last = entries[-1]
    return Place(last.filename, last.lineno or 0, (last.line or "").strip())


def user_traceback(exc: BaseException) -> str:
    """``exc``'s traceback with only the user's frames, chained exceptions included, as
    Python prints it (the exception's line alone when no frame is the user's: an error
    of compiled code raised by mimics for it)."""
    formatted = traceback.TracebackException.from_exception(exc)
    seen: set[int] = set()
    pending = [formatted]
    while pending:
        current = pending.pop()
        if id(current) in seen:
            continue
        seen.add(id(current))
        current.stack = traceback.StackSummary.from_list(
            [f for f in current.stack if is_user_file(f.filename)])
        pending.extend(e for e in (current.__cause__, current.__context__) if e is not None)
    return "".join(formatted.format())


def first_line(exc: BaseException) -> str:
    """The exception's message on one line (its class name when it has none)."""
    text = str(exc).strip()
    return text.splitlines()[0] if text else type(exc).__name__


# -- invalid outputs: which return produced them -----------------------------

def function_of(step: Any) -> FunctionType | None:
    """The Python function behind a step: a function, a bound method, a callable object."""
    target = inspect.unwrap(step) if callable(step) else step
    target = getattr(target, "__func__", target)
    if isinstance(target, FunctionType):
        return target
    call = inspect.getattr_static(type(step), "__call__", None)
    return call if isinstance(call, FunctionType) else None


def return_lines(step: Any, output: Any) -> list[Place]:
    """The ``return`` lines of ``step``'s function that can have returned ``output``.

    Read from the function's source: a value that is not two numbers cannot
    come from ``return a, b``; ``None`` comes from a bare ``return`` or from
    running off the end of the function (its ``def`` line is given then).
    Several candidates are all given, in the file's order; none when the
    source is not available.
    """
    function = function_of(step)
    if function is None or not is_user_file(function.__code__.co_filename):
        return []
    parsed = _returns_of(function.__code__, function)
    if parsed is None:
        return []
    returns, def_line, falls_off = parsed
    places = [line for line, value in returns if _could_return(value, output)]
    if output is None and falls_off:
        places.append(def_line)  # it ran off its end: name its `def`
    if not places:  # none fits only if the forms misjudged: name every return
        places = [line for line, _ in returns]
    filename = function.__code__.co_filename
    return [Place(filename, line, source_line(filename, line)) for line in sorted(set(places))]


@functools.lru_cache(maxsize=64)
def _returns_of(code: CodeType, function: FunctionType
                ) -> tuple[list[tuple[int, ast.expr | None]], int, bool] | None:
    """A function's ``(line, value)`` returns, its ``def`` line and whether it can run off
    its end; parsed once per function (2,000 robots failing at once parse it once)."""
    try:
        lines, first = inspect.getsourcelines(function)
        tree = ast.parse(textwrap.dedent("".join(lines)))
    except (OSError, TypeError, SyntaxError):
        return None
    definition = next((node for node in ast.walk(tree)
                       if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)), None)
    if definition is None:
        return None
    returns = [(node.lineno + first - 1, node.value) for node in _own_nodes(definition)
               if isinstance(node, ast.Return)]
    return returns, definition.lineno + first - 1, not _always_returns(definition.body)


def _own_nodes(function: ast.AST) -> list[ast.AST]:
    """The nodes of ``function``'s body, not those of functions or classes inside it."""
    found: list[ast.AST] = []
    pending = list(ast.iter_child_nodes(function))
    while pending:
        node = pending.pop()
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef | ast.Lambda):
            continue
        found.append(node)
        pending.extend(ast.iter_child_nodes(node))
    return found


def _could_return(value: ast.expr | None, output: Any) -> bool:
    """Whether ``return value`` can give ``output`` (judged by the expression's form only)."""
    if value is None or (isinstance(value, ast.Constant) and value.value is None):
        return output is None
    if output is None:
        return not isinstance(value, ast.Tuple | ast.List | ast.Constant)
    if isinstance(value, ast.Tuple | ast.List):
        if any(isinstance(e, ast.Starred) for e in value.elts):
            return True
        try:
            values = list(output)
        except TypeError:
            return False
        return len(values) == len(value.elts) and all(
            _could_return(element, item) for element, item in zip(value.elts, values, strict=True)
            if isinstance(element, ast.Constant))  # `return 0.0, theta` gave no NaN speed
    if isinstance(value, ast.Constant):
        return _same_number(value.value, output)
    return True


def _same_number(constant: Any, output: Any) -> bool:
    """Whether a literal in the source equals an output value (NaN equal to NaN)."""
    try:
        if constant == output:
            return True
        return math.isnan(float(constant)) and math.isnan(float(output))
    except (TypeError, ValueError):
        return False


def _always_returns(body: list[ast.stmt]) -> bool:
    """Whether a block surely ends in a return or a raise (so the function never falls off)."""
    if not body:
        return False
    last = body[-1]
    if isinstance(last, ast.Return | ast.Raise):
        return True
    if isinstance(last, ast.If):
        return _always_returns(last.body) and _always_returns(last.orelse)
    if isinstance(last, ast.While) and isinstance(last.test, ast.Constant) and last.test.value:
        return True  # `while True:` ends by a return, a raise or a break
    if isinstance(last, ast.With | ast.AsyncWith):
        return _always_returns(last.body)
    if isinstance(last, ast.Try):
        return (_always_returns(last.body) or _always_returns(last.orelse)) and all(
            _always_returns(h.body) for h in last.handlers)
    return False


def where_of(places: list[Place]) -> tuple[str, str]:
    """``(where, text)``: ``"my_algo.py:7"`` (``"my_algo.py:7 or 12"`` for several) and the
    first place's source line (``("", "")`` for none)."""
    if not places:
        return "", ""
    first = places[0]
    where = str(first)
    if len(places) > 1:
        where += " or " + " or ".join(str(p.line) for p in places[1:])
    return where, first.text
