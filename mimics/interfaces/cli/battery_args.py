"""What the battery commands share: the folder argument, its records, the wide table console.

Their own module so that ``battery`` (the commands) and ``battery_report`` (the
report's parts) both import it, and not each other.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console

Folder = Annotated[Path, typer.Argument(help="A battery folder (the --out of `battery run`).")]


def table_console() -> Console:
    """Standard output; wide tables when it is a file or a pipe, not a terminal."""
    console = Console(highlight=False)
    return console if console.is_terminal else Console(highlight=False, width=220)


def battery_records(folder: Path) -> Any:
    """``folder`` as an input whose records (the database, its journal, the runs, the
    copy of the battery file) no output may overwrite; reports may go beside them."""
    from mimics.batteries.store import DB_NAME, RUNS_DIR, TMP_DIR, WORKERS_DIR
    from mimics.world.output_paths import Folder as InputFolder

    journal = tuple(f"{DB_NAME}{end}" for end in ("", "-wal", "-shm", "-journal"))
    return InputFolder(folder, (*journal, f".{DB_NAME}.new", "battery.toml", "battery.lock",
                                RUNS_DIR, TMP_DIR, WORKERS_DIR))
