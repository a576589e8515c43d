"""One-line messages shared by every CLI module (errors exit with status 2)."""

from __future__ import annotations

import typer
from rich.console import Console

#: Exit statuses (see ``mimics --help`` and docs/reference/exit-status.md).
EXIT_OK, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_INTERRUPTED = 0, 1, 2, 130


def fail(message: str) -> typer.Exit:
    """Print a one-line error on stderr; returns the exit to raise (status 2)."""
    Console(stderr=True, highlight=False, soft_wrap=True).print(f"mimics: error: {message}",
                                                                markup=False)
    return typer.Exit(2)


def say(message: str) -> None:
    """Print a plain line on stdout, without Rich markup."""
    Console(highlight=False, soft_wrap=True).print(message, markup=False)


def note(message: str) -> None:
    """Print a plain line on stderr (progress notes that are not results)."""
    Console(stderr=True, highlight=False, soft_wrap=True).print(message, markup=False)
