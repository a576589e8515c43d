"""Error messages worded for the page, not for the command line.

The readers' messages (:class:`~mimics.world.errors.MimicsError`) are written
for a terminal: they name the file and line, and give command-line advice.
The page shows them after rewording: paths relative to the workspace (never a
server's temporary folder), the page's words for a scenario it has not written
yet ("robot 2" rather than "robots[2] (line 3)"), no ``--allow-overlap``
advice, and one sentence for a request the API refused.

>>> scenario_for_page("/ws/scenarios/a.toml: robots[2] (line 3): robot at (0.1, 1) touches "
...                   "wall 3 (1 start problem(s); keep them on purpose with --allow-overlap "
...                   "or allow_overlap = true in [settings])")
'robot 2: robot at (0.1, 1) touches wall 3'
>>> validation_for_page([{"type": "too_short", "loc": ["body", "robots"], "msg": "List ...",
...                       "ctx": {"min_length": 1, "actual_length": 0}}])
'a scenario needs at least one robot: place robots on the map first'
>>> validation_for_page([{"type": "unknown_field", "loc": ["body", "scenarios", 0],
...                       "msg": "nmae: unknown field (expected name, params)"}])
'scenarios[0].nmae: unknown field (expected name, params)'
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path
from typing import Any

_ADVICE = re.compile(r" \((\d+) start problem\(s\); keep them on purpose with --allow-overlap"
                     r" or allow_overlap = true in \[settings\]\)")
_FILE_PREFIX = re.compile(r"^\S+?\.toml(, line \d+)?: ")
_ROBOT = re.compile(r"robots\[(\d+)\](?: \(line \d+\))?")
_TYPE_FIELD = re.compile(r"robot (\d+)\.type: ")
_SETTING = re.compile(r"^settings\.(\w+): ")
_TOML_ADVICE = re.compile(r",? or define it in \[types\.[^\]]*\]")

#: Field names of the API's bodies as the page labels them.
_FIELDS = {"robots": "robots", "bounds": "map bounds", "segments": "walls", "path": "file",
           "time_limit": "time limit", "goal": "goal", "seeds": "seeds", "count": "count",
           "min_spacing": "min spacing", "region": "region"}


def paths_for_page(message: str, workspace: Path) -> str:
    """``message`` with the workspace's absolute path made relative to it."""
    root = str(workspace)
    return message.replace(root + "/", "").replace(root, ".")


def upload_for_page(message: str, folder: str | Path, filename: str) -> str:
    """``message`` about a file uploaded into the temporary ``folder``, naming the upload
    as the user called it (the server's temporary path means nothing to the page)."""
    return message.replace(f"{Path(folder) / filename}", filename).replace(str(folder), "")


def scenario_for_page(message: str, custom_types: dict[str, Any] | None = None) -> str:
    """A reader's message about the scenario the page sent, in the page's words.

    The scenario is checked before it is written, so no file or line is named;
    robots are named by their number, a setting by its label, a sensor type the
    page made up (``Pioneer2DX_b-3_r8_n0``) by its base type's sensors.
    """
    text = _ADVICE.sub(lambda m: "" if m.group(1) == "1"
                       else f" ({m.group(1)} start problems)", message)
    text = _FILE_PREFIX.sub("", text)
    text = _ROBOT.sub(lambda m: f"robot {m.group(1)}", text)
    text = _TYPE_FIELD.sub(lambda m: f"robot {m.group(1)}'s type: ", text)
    text = _TOML_ADVICE.sub("", text)
    text = _SETTING.sub(lambda m: f"{m.group(1).replace('_', ' ')}: ", text)
    for name, entry in (custom_types or {}).items():
        base = entry.get("base", name) if isinstance(entry, dict) else name
        text = text.replace(f"robot type '{name}': ranger ", f"sensors of {base}: ")
        text = text.replace(f"robot type '{name}': ", f"{base} with these sensors: ")
    return text


def validation_for_page(errors: Sequence[Any]) -> str:
    """One sentence for the API's refusal of a request body (pydantic's errors)."""
    lines = []
    for error in errors:
        loc = list(error.get("loc", ()))
        if loc and loc[0] in ("body", "query", "path", "header"):  # where, not which field
            loc = loc[1:]
        location = [str(part) for part in loc]
        field = location[0] if location else "request"
        label = _FIELDS.get(field, field.replace("_", " "))
        context = error.get("ctx") or {}
        kind = error.get("type", "")
        if kind == "unknown_field":  # StrictBody: the message names the key and the known
            where = "".join(f"[{part}]" if part.isdigit() else f".{part}" for part in location)
            lines.append(f"{where.lstrip('.')}.{error.get('msg')}" if where
                         else str(error.get("msg")))
        elif field == "robots" and kind == "too_short" and len(location) == 1:
            lines.append("a scenario needs at least one robot: place robots on the map first")
        elif kind == "too_short":
            lines.append(f"{label}: expected at least {context.get('min_length')} values, "
                         f"got {context.get('actual_length')}")
        elif kind == "too_long":
            lines.append(f"{label}: expected at most {context.get('max_length')} values")
        elif kind == "missing":
            lines.append(f"{label}: missing")
        elif kind.startswith(("greater_than", "less_than")):
            bound = next(iter(context.values()), "")
            words = {"greater_than": "above", "greater_than_equal": "at least",
                     "less_than": "below", "less_than_equal": "at most"}[kind]
            lines.append(f"{label}: expected a number {words} {bound}")
        else:
            message = str(error.get("msg", "not valid"))
            lines.append(f"{label}: {message[:1].lower()}{message[1:]}")
    return "; ".join(lines) or "the request was not valid"
