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

    def line_of(self, key: tuple[Any, ...]) -> int | None:
        """Best-effort line of a key path like ``("robots", 2, "x")`` or ``("settings", "dt")``."""
        table: tuple[Any, ...] = ()
        aot_seen: dict[str, int] = {}
        header = re.compile(r"^\s*(\[\[?)\s*([A-Za-z0-9_.\"' -]+?)\s*\]\]?\s*(#.*)?$")
        assign = re.compile(r"^\s*(\"[^\"]*\"|[A-Za-z0-9_-]+)\s*=")
        found: int | None = None
        inline_array: tuple[str, int] | None = None  # (key, line) of "key = [" at top level
        for number, line in enumerate(self.lines, start=1):
            head = header.match(line)
            if head and not inline_array:
                parts = tuple(p.strip().strip('"') for p in head.group(2).split("."))
                if head.group(1) == "[[":
                    aot_seen[parts[0]] = aot_seen.get(parts[0], -1) + 1
                    table = (parts[0], aot_seen[parts[0]])
                else:
                    table = parts
                if table == key[:len(table)] and len(table) == len(key):
                    return number
                if table == key[:len(table)]:
                    found = number
                continue
            if inline_array:
                if line.strip().startswith("]"):
                    inline_array = None
                    continue
                name, start = inline_array
                if line.strip().startswith("{") and key[:1] == (name,) and len(key) > 1:
                    index = sum(1 for ln in self.lines[start:number - 1]
                                if ln.strip().startswith("{"))
                    if index == key[1]:
                        return number
                continue
            match = assign.match(line)
            if not match:
                continue
            name = match.group(1).strip('"')
            if table == () and line.rstrip().endswith("[") and name == key[0]:
                inline_array = (name, number)
            if (*table, name) == key[:len(table) + 1] and table == key[:len(table)]:
                return number
        return found

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
