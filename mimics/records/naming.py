"""The default name of a run folder, never one already taken.

A run folder is named from the scenario's name, the algorithm and the seed
(``runs/room-go_to_goal-s1``). Two scenarios may share a name (a copy of
``room.toml`` saved as ``small.toml`` is still called "room"), and one may be run
twice: a new run never replaces an earlier one silently, it gets ``-2``, ``-3``...

>>> import tempfile
>>> parent = Path(tempfile.mkdtemp())
>>> new_run_folder(parent, "room", "go_to_goal", 1).name
'room-go_to_goal-s1'
>>> new_run_folder(parent, "room", "go_to_goal", 1).name
'room-go_to_goal-s1-2'
>>> new_run_folder(parent, "a/b c", "go_to_goal", 1).name
'a_b_c-go_to_goal-s1'
"""

from __future__ import annotations

import re
from pathlib import Path

from mimics.world.errors import MimicsError

#: Characters kept in a folder name; any run of others becomes one ``_``.
_UNSAFE = re.compile(r"[^A-Za-z0-9._=+-]+")
MAX_TRIES = 10_000


def run_folder_name(scenario: str, algorithm: str, seed: int) -> str:
    """``SCENARIO-ALGORITHM-sSEED`` with characters unsafe in a path replaced by ``_``."""
    return _UNSAFE.sub("_", f"{scenario}-{algorithm}-s{seed}")


def new_run_folder(parent: str | Path, scenario: str, algorithm: str, seed: int) -> Path:
    """Create and return an empty run folder under ``parent``: the default name, else the
    first free of ``NAME-2``, ``NAME-3``... (created here, so two runs started at once
    cannot pick the same one).

    Raises:
        MimicsError: when ``parent`` cannot be written.
    """
    root = Path(parent)
    base = run_folder_name(scenario, algorithm, seed)
    try:
        root.mkdir(parents=True, exist_ok=True)
        for number in range(1, MAX_TRIES + 1):
            folder = root / (base if number == 1 else f"{base}-{number}")
            try:
                folder.mkdir()
            except FileExistsError:
                continue
            return folder
    except OSError as exc:
        raise MimicsError(f"{root}: cannot make a run folder here "
                          f"({exc.strerror or exc})") from None
    raise MimicsError(f"{root}: {MAX_TRIES} run folders named {base}-N already; "
                      "remove old runs or give --out")
