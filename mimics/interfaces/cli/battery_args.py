"""What the battery commands share: the folder argument and the wide table console.

Their own module so that ``battery`` (the commands) and ``battery_report`` (the
report's parts) both import it, and not each other.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import typer
from rich.console import Console

Folder = Annotated[Path, typer.Argument(help="A battery folder (the --out of `battery run`).")]


def table_console() -> Console:
    """Standard output; wide tables when it is a file or a pipe, not a terminal."""
    console = Console(highlight=False)
    return console if console.is_terminal else Console(highlight=False, width=220)
