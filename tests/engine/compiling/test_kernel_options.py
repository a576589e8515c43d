"""Kernels compiled without a Python wrapper (``kernel_options.INNER``) are called by
kernels only: a call from Python would not raise but crash the interpreter."""

from __future__ import annotations

import ast
import importlib
import pkgutil
from pathlib import Path

import mimics
import mimics.engine

ROOTS = (Path(mimics.__file__).parent, Path(__file__).parents[2], Path(__file__).parents[3]
         / "benchmarks")


def _inner_kernels() -> set[str]:
    """Names of the engine's kernels compiled without a CPython wrapper."""
    names = set()
    for info in pkgutil.walk_packages(mimics.engine.__path__, "mimics.engine."):
        module = importlib.import_module(info.name)
        for name, value in vars(module).items():
            options = getattr(value, "targetoptions", None)
            if isinstance(options, dict) and options.get("no_cpython_wrapper"):
                names.add(name)
    return names


def _compiled(function: ast.FunctionDef) -> bool:
    return any("njit" in ast.unparse(d) or "jit" in ast.unparse(d).split("(")[0]
               for d in function.decorator_list)


def _python_calls() -> dict[str, str]:
    """Each name called outside compiled functions, with where (every module of the
    package, the tests and the benchmarks)."""
    calls: dict[str, str] = {}
    for root in ROOTS:
        for path in root.rglob("*.py"):
            tree = ast.parse(path.read_text(encoding="utf-8"))
            compiled = [(f.lineno, f.end_lineno or f.lineno) for f in ast.walk(tree)
                        if isinstance(f, ast.FunctionDef) and _compiled(f)]
            # the names this file can mean an engine kernel by: imported from the engine
            # or compiled here
            known = {a.asname or a.name for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)
                     and (n.module or "").startswith("mimics.engine") for a in n.names}
            known |= {f.name for f in tree.body if isinstance(f, ast.FunctionDef) and _compiled(f)}
            for call in ast.walk(tree):
                if isinstance(call, ast.Call) and ast.unparse(call.func) in known and not any(
                        first <= call.lineno <= last for first, last in compiled):
                    calls.setdefault(ast.unparse(call.func), f"{path}:{call.lineno}")
    return calls


def _doctest_calls() -> dict[str, str]:
    """Each name called on a doctest line (``>>> ...``) of the package and the docs."""
    calls: dict[str, str] = {}
    paths = [*ROOTS[0].rglob("*.py"), *(ROOTS[2].parent / "docs").rglob("*.md"),
             ROOTS[2].parent / "README.md"]
    for path in paths:
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            code = line.strip().removeprefix(">>> ")
            if line.strip().startswith(">>> "):
                try:
                    tree = ast.parse(code)
                except SyntaxError:  # a line continued on the next ("...")
                    continue
                for call in (c for c in ast.walk(tree) if isinstance(c, ast.Call)):
                    calls.setdefault(ast.unparse(call.func).rsplit(".", 1)[-1],
                                     f"{path}:{number}")
    return calls


def test_no_inner_kernel_is_called_from_python() -> None:
    inner = _inner_kernels()
    assert "_scan_row" in inner and "_sweep_block" in inner  # the check sees them
    calls = {**_doctest_calls(), **_python_calls()}
    assert {name: calls[name] for name in inner & set(calls)} == {}
