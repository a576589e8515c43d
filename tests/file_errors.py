"""The one-line error a reader gives for a bad input file, shared by the readers' tests."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from mimics.world.errors import MimicsError


def file_error(read: Callable[[Path], object], path: Path, text: str, *,
               match: str | None = None, line: int | None = None,
               error: type[MimicsError] = MimicsError) -> str:
    """Write ``text`` to ``path``, have ``read`` read it, and return the ``error`` it raised
    (matching ``match``), after checking that its message is one line naming the file first
    (then ``line``, if given)."""
    path.write_text(text)
    with pytest.raises(error, match=match) as info:
        read(path)
    message = str(info.value)
    named = str(path) if line is None else f"{path}, line {line}: "
    assert message.startswith(named), message
    assert "\n" not in message, message
    return message
