"""Errors for bad input: each names the file, key or argument and what was expected."""

from __future__ import annotations

from pathlib import Path


class MimicsError(Exception):
    """Base of every error mimics raises on purpose; the CLI prints it in one line, exit 2.

    The message is one line whatever it quotes (a YAML parser's two-line
    complaint, a file's text): runs of white space, newlines included, become
    one space.
    """

    def __str__(self) -> str:
        return " ".join(super().__str__().split())


class ScenarioError(MimicsError, ValueError):
    """A scenario, robot type or map is malformed."""


class AlgorithmError(MimicsError, ValueError):
    """An algorithm cannot be found or does not follow the contract."""


def read_input_text(path: Path, kind: str, error: type[MimicsError] = MimicsError) -> str:
    """The UTF-8 text of an input file (``kind``: "scenario", "battery"...).

    Raises:
        error: one line naming the file and what went wrong.
    """
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{path}: {kind} file not found") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise error(f"{path}: cannot read this {kind} file ({exc})") from None
