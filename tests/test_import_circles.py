"""No import circles among mimics' modules (the developers' guide), counting every import:
function-level ones and those only for type checkers (``if TYPE_CHECKING:``) too, since
a circle a type checker follows is one a reader follows."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import mimics

PACKAGE = Path(mimics.__file__).parent


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported(path: Path, known: set[str]) -> set[str]:
    """The mimics modules ``path`` imports, wherever in the file."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return names & known


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(module: str) -> None:
        index[module] = low[module] = len(index)
        stack.append(module)
        for other in sorted(graph[module]):
            if other not in index:
                visit(other)
                low[module] = min(low[module], low[other])
            elif other in stack:
                low[module] = min(low[module], index[other])
        if low[module] == index[module]:
            component = []
            while True:
                top = stack.pop()
                component.append(top)
                if top == module:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for module in sorted(graph):
        if module not in index:
            visit(module)
    return found


def test_the_finder_finds_a_circle() -> None:
    assert circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert circles({"a": {"b"}, "b": set()}) == []


def test_no_module_of_mimics_is_in_an_import_circle() -> None:
    files = {module_name(path): path for path in PACKAGE.rglob("*.py")}
    graph = {name: imported(path, set(files)) - {name} for name, path in files.items()}
    assert circles(graph) == []


PAGE_SCRIPTS = PACKAGE / "interfaces" / "web" / "static" / "js"
JS_IMPORT = re.compile(r"""(?:^|\n)\s*import\b[^;]*?\bfrom\s+["']\./([\w.]+\.js)["']""")


def test_the_page_scripts_are_found_and_read() -> None:
    graph = page_imports()
    assert len(graph) >= 10 and "app.js" in graph
    assert {"live.js", "runs.js"} <= graph["app.js"]


def page_imports() -> dict[str, set[str]]:
    """Each of the workbench's page scripts -> the scripts it imports (ES modules)."""
    return {path.name: set(JS_IMPORT.findall(path.read_text(encoding="utf-8")))
            for path in PAGE_SCRIPTS.glob("*.js")}


def test_no_page_script_is_in_an_import_circle() -> None:
    assert circles(page_imports()) == []
