"""A battery given in a notebook: its functions and classes, and a cell run again.

:func:`with_inline_algorithms` turns the functions and classes of a battery
dict's ``algorithms`` into ``pickle:`` texts (:mod:`~mimics.interfaces.notebook.pickled`),
so that they reach the workers; :func:`same_battery` tells whether a folder
already holds the battery asked for (a cell run twice: it is continued or just
opened) or another one (refused, naming what differs).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from mimics.world.errors import MimicsError


def with_inline_algorithms(table: dict[str, Any]) -> dict[str, Any]:
    """A battery dict with its functions and classes in ``algorithms`` as ``pickle:``
    texts (:mod:`mimics.interfaces.notebook.pickled`); the dict given is not changed."""
    from mimics.interfaces.notebook.pickled import algorithm_ref, is_inline_algorithm

    battery = table.get("battery")
    if not isinstance(battery, dict):
        return table  # spec_from_dict names what is missing
    given = battery.get("algorithms")
    listed = [given] if is_inline_algorithm(given) else given
    if not isinstance(listed, list | tuple):
        return table
    algorithms = [algorithm_ref(a) if is_inline_algorithm(a) else a for a in listed]
    return {**table, "battery": {**battery, "algorithms": algorithms}}


def same_battery(out: Path, spec: Any) -> bool:
    """Whether ``out`` holds ``spec``'s battery already (False: no battery there).

    Raises:
        MimicsError: ``out`` holds another battery, naming what differs.
    """
    from mimics.batteries.store import DB_NAME, BatteryStore

    if not (out / DB_NAME).is_file():
        if out.exists() and (not out.is_dir() or any(out.iterdir())):
            raise MimicsError(f"run_battery: out: {str(out)!r} holds other files, not a "
                              "battery: give a new or empty folder as out=")
        return False
    store = BatteryStore.open(out)
    try:
        held = _comparable(store.spec())
    finally:
        store.close()
    wanted = _comparable(spec)
    if held == wanted:
        return True
    differ = sorted(key for key in held.keys() | wanted.keys() if held.get(key) != wanted.get(key))
    raise MimicsError(
        f"run_battery: out: {str(out)!r} holds another battery (different "
        f"{', '.join(differ)}): give a new folder as out=, or open that "
        f"one with mimics.load_battery({str(out)!r})")


def _comparable(spec: Any) -> dict[str, Any]:
    """A spec as a dict, algorithms defined in a notebook by their name and code only."""
    from mimics.interfaces.notebook.pickled import without_pickles

    data: dict[str, Any] = json.loads(spec.to_json())
    data["algorithms"] = [without_pickles(a) for a in data.get("algorithms", [])]
    return data
