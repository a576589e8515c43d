"""The user's config folder: the last saved battery, for ``mimics battery run --last``.

The folder is ``platformdirs.user_config_dir("mimics")`` (``~/.config/mimics``
on Linux), or ``$MIMICS_CONFIG_DIR`` when set (tests use it). The last battery
is kept in ``last_battery.toml`` as ``path = "/abs/path/battery.toml"``.
"""

from __future__ import annotations

import os
import tomllib
from pathlib import Path

from mimics.world.errors import MimicsError

ENV_VAR = "MIMICS_CONFIG_DIR"
LAST_FILE = "last_battery.toml"


def config_dir() -> Path:
    """The user's mimics config folder (not created)."""
    override = os.environ.get(ENV_VAR)
    if override:
        return Path(override)
    import platformdirs

    return Path(platformdirs.user_config_dir("mimics", appauthor=False))


def remember_battery(path: str | Path) -> None:
    """Record ``path`` as the last saved battery; a config folder that cannot be
    written is not an error (the shortcut is a convenience)."""
    import tomli_w

    folder = config_dir()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        temporary = folder / f".{LAST_FILE}.{os.getpid()}"
        temporary.write_text(tomli_w.dumps({"path": str(Path(path).resolve())}))
        os.replace(temporary, folder / LAST_FILE)
    except OSError:
        pass


def last_battery() -> Path:
    """The last saved battery file.

    Raises:
        MimicsError: when none was saved, or it no longer exists.
    """
    where = config_dir() / LAST_FILE
    try:
        path = Path(tomllib.loads(where.read_text())["path"])
    except FileNotFoundError:
        raise MimicsError("--last: no battery saved yet (run `mimics battery new` or "
                          "`mimics battery run FILE` once)") from None
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise MimicsError(f"--last: {where} is unreadable ({exc})") from None
    if not path.is_file():
        raise MimicsError(f"--last: the last battery file {path} no longer exists")
    return path
