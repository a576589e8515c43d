"""Where map data that mimics does not ship lives (the Stage bitmaps and worlds).

The data folder is, in order:

1. the ``MIMICS_DATA`` environment variable, if set;
2. the user data folder (``platformdirs``), if it holds ``stage/``;
3. ``shared/data`` beside a development checkout (found by walking up from
   the package folder), if it holds ``stage/``;
4. otherwise the user data folder, where ``mimics data get stage`` puts it.

>>> import os
>>> os.environ["MIMICS_DATA"] = "/tmp/my-data"
>>> str(data_folder())
'/tmp/my-data'
>>> del os.environ["MIMICS_DATA"]
"""

from __future__ import annotations

import os
from pathlib import Path

import platformdirs

from mimics.world.errors import MimicsError

ENV_VAR = "MIMICS_DATA"
STAGE = "stage"


def user_data_folder() -> Path:
    """The per-user data folder of mimics (it may not exist yet)."""
    return platformdirs.user_data_path("mimics", appauthor=False)


def _checkout_data_folder() -> Path | None:
    """``shared/data`` beside a development checkout, if it holds ``stage/``."""
    here = Path(__file__).resolve().parent
    for folder in here.parents:
        candidate = folder / "shared" / "data"
        if (candidate / STAGE).is_dir():
            return candidate
    return None


def data_folder() -> Path:
    """The folder that holds mimics' map data (see the module docstring for the order)."""
    env = os.environ.get(ENV_VAR)
    if env:
        return Path(env).expanduser()
    user = user_data_folder()
    if (user / STAGE).is_dir():
        return user
    return _checkout_data_folder() or user


def download_folder() -> Path:
    """Where ``mimics data get`` writes by default: ``MIMICS_DATA`` or the user data folder."""
    env = os.environ.get(ENV_VAR)
    return Path(env).expanduser() if env else user_data_folder()


def find_stage_file(name: str) -> Path:
    """The path of a Stage data file (``cave_filled.png``, ``hospital.world``...).

    Raises:
        MimicsError: the file is not in the data folder; the message says how to get it.
    """
    folder = data_folder() / STAGE
    path = folder / name
    if not path.is_file():
        raise MimicsError(f"Stage data file {name!r} not found in {folder}: run "
                          f"`mimics data get stage` (or set {ENV_VAR} to a folder holding "
                          f"{STAGE}/)")
    return path
