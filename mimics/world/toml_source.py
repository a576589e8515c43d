"""Reading a TOML file strictly: keys located to their line, one-line errors naming them.

:class:`TomlSource` finds the line of a key path and raises the
:class:`~mimics.world.errors.ScenarioError` lines; :class:`TableReader` gives typed
access to one table, rejecting unknown keys. Shared by the scenario file's readers
(:mod:`mimics.world.scenario_parts`).
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

from mimics.world.errors import ScenarioError
from mimics.world.limits import MAX_ROBOTS


class TomlSource:
    """The file being read: names keys, finds their lines, raises the one-line errors."""

    def __init__(self, path: Path, text: str) -> None:
        self.path = path
        self.lines = text.splitlines()
        self._index: tuple[dict, dict, list] | None = None

    def line_of(self, key: tuple[Any, ...]) -> int | None:
        """Best-effort line of a key path like ``("robots", 2, "x")`` or ``("settings", "dt")``.

        The file is indexed once, so naming every robot of a 2,000-robot file stays linear."""
        if self._index is None:
            self._index = self._build_index()
        exact, prefixes, headers = self._index
        if key in exact:
            return exact[key]
        for size in range(len(key), 0, -1):
            if key[:size] in prefixes:
                return prefixes[key[:size]]
        found = None
        for table, number in headers:
            if table == key[:len(table)]:
                found = number
        return found

    def _build_index(self) -> tuple[dict, dict, list]:
        """Header lines (exact table paths), assignment and inline-array-item lines, and
        every header in file order (for the nearest enclosing table)."""
        header = re.compile(r"^\s*(\[\[?)\s*([A-Za-z0-9_.\"' -]+?)\s*\]\]?\s*(#.*)?$")
        assign = re.compile(r"^\s*(\"[^\"]*\"|[A-Za-z0-9_-]+)\s*=")
        exact: dict[tuple[Any, ...], int] = {}
        prefixes: dict[tuple[Any, ...], int] = {}
        headers: list[tuple[tuple[Any, ...], int]] = []
        table: tuple[Any, ...] = ()
        aot_seen: dict[str, int] = {}
        inline_array: list[Any] | None = None  # [key, items seen] of "key = [" at top level
        for number, line in enumerate(self.lines, start=1):
            head = header.match(line)
            if head and not inline_array:
                parts = tuple(p.strip().strip('"') for p in head.group(2).split("."))
                if head.group(1) == "[[":
                    aot_seen[parts[0]] = aot_seen.get(parts[0], -1) + 1
                    table = (parts[0], aot_seen[parts[0]])
                else:
                    table = parts
                exact.setdefault(table, number)
                headers.append((table, number))
                continue
            if inline_array:
                if line.strip().startswith("]"):
                    inline_array = None
                elif line.strip().startswith("{"):
                    prefixes.setdefault((inline_array[0], inline_array[1]), number)
                    inline_array[1] += 1
                continue
            match = assign.match(line)
            if not match:
                continue
            name = match.group(1).strip('"')
            if table == () and line.rstrip().endswith("["):
                inline_array = [name, 0]
            prefixes.setdefault((*table, name), number)
        return exact, prefixes, headers

    def error(self, key: tuple[Any, ...], message: str) -> ScenarioError:
        line = self.line_of(key) if key else None
        where = f"{self.path}, line {line}" if line else f"{self.path}"
        name = "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in key).lstrip(".")
        return ScenarioError(f"{where}: {name}: {message}" if name else f"{where}: {message}")


def is_number(value: Any) -> bool:
    return (isinstance(value, int | float) and not isinstance(value, bool)
            and math.isfinite(value))


class TableReader:
    """Typed access to one table of the file, rejecting unknown keys."""

    def __init__(self, src: TomlSource, key: tuple[Any, ...], data: Any, allowed: tuple[str, ...],
                 what: str = "a table") -> None:
        if not isinstance(data, dict):
            raise src.error(key, f"expected {what}, got {data!r}")
        for name in data:
            if name not in allowed:
                raise src.error((*key, name), f"unknown key (expected one of "
                                               f"{', '.join(allowed)})")
        self.src, self.key, self.data = src, key, data

    def has(self, name: str) -> bool:
        return name in self.data

    def fail(self, name: str, message: str) -> ScenarioError:
        return self.src.error((*self.key, name), message)

    def number(self, name: str, default: float | None = None) -> float:
        value = self.data.get(name, default)
        if value is None:
            raise self.src.error(self.key, f"missing key {name!r} (expected a number)")
        if not is_number(value):
            raise self.fail(name, f"expected a number, got {value!r}")
        return float(value)

    def integer(self, name: str, minimum: int, default: int | None = None,
                maximum: int = MAX_ROBOTS) -> int:
        value = self.data.get(name, default)
        if value is None:
            raise self.src.error(self.key, f"missing key {name!r} (expected a whole number)")
        if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
            raise self.fail(name, f"expected a whole number >= {minimum}, got {value!r}")
        if value > maximum:
            raise self.fail(name, f"{value} is over the limit of {maximum}")
        return value

    def numbers(self, name: str, size: int, default: Any = None, what: str = "") -> Any:
        value = self.data.get(name, default)
        shape = what or f"[{', '.join('n' * size)}]"
        if value is None:
            raise self.src.error(self.key, f"missing key {name!r} (expected {shape})")
        if (not isinstance(value, list | tuple) or len(value) != size
                or not all(is_number(v) for v in value)):
            raise self.fail(name, f"expected {shape}, got {value!r}")
        return tuple(float(v) for v in value)

    def string(self, name: str, default: str | None = None) -> str:
        value = self.data.get(name, default)
        if value is None:
            raise self.src.error(self.key, f"missing key {name!r} (expected a string)")
        if not isinstance(value, str):
            raise self.fail(name, f"expected a string, got {value!r}")
        return value
