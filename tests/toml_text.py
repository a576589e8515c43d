"""TOML text from Python values, one ``key = value`` a line, for the tests' input files.

tomli_w would do, but it spreads arrays over several lines; the fuzzers damage a
file line by line and the error tests name lines, so each key stays on its own.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any


def toml_value(value: Any) -> str:
    """``value`` (bool, number, string, list or dict) as an inline TOML value."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)  # a JSON string of plain text is a TOML basic string
    if isinstance(value, list | tuple):
        return "[" + ", ".join(toml_value(item) for item in value) + "]"
    if isinstance(value, Mapping):
        return "{ " + ", ".join(f"{key} = {toml_value(item)}" for key, item in value.items()) + " }"
    return repr(value)


def _keys(table: Mapping[str, Any]) -> list[str]:
    return [f"{key} = {toml_value(value)}" for key, value in table.items()]


def toml_text(document: Mapping[str, Any]) -> str:
    """``document`` as TOML: its plain keys first, then a ``[[key]]`` block for each table
    of a list of tables, a ``[key.name]`` block for each table of a table of tables and a
    ``[key]`` block for any other table, blocks apart by a blank line."""
    blocks = []
    plain = {key: value for key, value in document.items() if not _is_block(value)}
    if plain:
        blocks.append(_keys(plain))
    for key, value in document.items():
        if isinstance(value, list) and _is_block(value):
            blocks += [[f"[[{key}]]", *_keys(item)] for item in value]
        elif isinstance(value, Mapping) and all(isinstance(v, Mapping) for v in value.values()):
            blocks += [[f"[{key}.{name}]", *_keys(table)] for name, table in value.items()]
        elif isinstance(value, Mapping):
            blocks.append([f"[{key}]", *_keys(value)])
    return "\n\n".join("\n".join(lines) for lines in blocks) + "\n"


def _is_block(value: Any) -> bool:
    """Whether ``value`` is written as blocks of its own (a table, or a list of tables)."""
    if isinstance(value, list):
        return bool(value) and all(isinstance(item, Mapping) for item in value)
    return isinstance(value, Mapping)
