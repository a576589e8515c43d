"""Outputs that would overwrite what a command reads, refused before anything is written.

A command that reads files (a run folder, a battery folder, a map, a scenario)
and writes others calls :func:`check_outputs` before it reads or writes
anything. An output is refused, in one line naming its option and path, when it

* is one of the inputs (also through ``..``, a symbolic link or a hard link),
* lies inside an input folder: anywhere in it, or, for a :class:`Folder` that
  names its records, in one of them (``RUN/run.png`` is where ``mimics plot``
  writes by default; ``RUN/trajectory.parquet`` is the run),
* holds an input (an output folder around a file the command reads), or
* is the same file as another output.

>>> import tempfile
>>> run = Path(tempfile.mkdtemp())
>>> check_outputs({"--mcap": run / "out.mcap"}, {"the run folder": run})  # doctest: +ELLIPSIS
Traceback (most recent call last):
...
mimics.world.errors.MimicsError: --mcap ...out.mcap: inside the run folder ... outside it)
>>> check_outputs({"--out": run / "run.png"}, {"the run folder": Folder(run, ("summary.json",))})
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mimics.world.errors import MimicsError

PathLike = str | os.PathLike[str]


@dataclass(frozen=True)
class Folder:
    """An input folder whose records are these names (files or folders) in it; outputs
    may go elsewhere in it. Without names (a plain path) nothing in it may be written."""

    path: PathLike
    records: tuple[str, ...] = ()


def resolved(path: Path) -> Path:
    """``path`` made absolute, its links and ``..`` followed as far as they exist."""
    try:
        return path.resolve()
    except (OSError, RuntimeError):  # a link loop: compare the path as written
        return path.absolute()


def same_file(a: Path, b: Path) -> bool:
    """Whether ``a`` and ``b`` name one file or folder (also through hard links)."""
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    return resolved(a) == resolved(b)


def is_inside(path: Path, folder: Path) -> bool:
    """Whether ``path`` lies strictly inside ``folder`` (both resolved)."""
    inner, outer = resolved(path), resolved(folder)
    return inner != outer and inner.is_relative_to(outer)


def check_outputs(outputs: Mapping[str, PathLike | None],
                  inputs: Mapping[str, PathLike | Folder | None]) -> None:
    """Refuse outputs that are an input, lie in an input folder, hold an input, or clash.

    Args:
        outputs: option name (``"--mcap"``) -> the path it writes (None: not given).
        inputs: what the command reads (``"the run folder"``) -> its path, or a
            :class:`Folder` naming its records (None: not given).

    Raises:
        MimicsError: one line naming the option, the path and the input it would overwrite.
    """
    given = [(name, Path(path)) for name, path in outputs.items()
             if path is not None and str(path) != ""]
    sources = [(what, item if isinstance(item, Folder) else Folder(item))
               for what, item in inputs.items() if item is not None and str(item) != ""]
    for name, out in given:
        for what, folder in sources:
            source = Path(folder.path)
            if same_file(out, source):
                raise MimicsError(f"{name} {out}: is {what} that this command reads "
                                  f"(expected a new path, not an input)")
            if source.is_dir() and _in_records(out, source, folder.records):
                raise MimicsError(f"{name} {out}: inside {what} {source}, whose records must "
                                  f"not be overwritten (expected a path outside it)")
            if is_inside(source, out):
                raise MimicsError(f"{name} {out}: holds {what} {source} that this command "
                                  f"reads (expected a path that does not contain it)")
    for k, (name, out) in enumerate(given):
        for other, path in given[k + 1:]:
            if same_file(out, path):
                raise MimicsError(f"{name} {out} and {other} {path}: the same file for two "
                                  f"outputs (expected two different paths)")


def _in_records(path: Path, folder: Path, records: tuple[str, ...]) -> bool:
    """Whether ``path`` is in ``folder`` (in one of its ``records``, when named), by path
    or as a hard link of a file there."""
    if is_inside(path, folder):
        if not records:
            return True
        first = resolved(path).relative_to(resolved(folder)).parts[0]
        if first in records:
            return True
    return _linked_into(path, folder, records)


def _linked_into(path: Path, folder: Path, records: tuple[str, ...]) -> bool:
    """Whether ``path`` is an existing file with other hard links, one of them in
    ``folder`` (in one of its ``records``, when named)."""
    try:
        stat = path.stat()
    except OSError:
        return False
    if not path.is_file() or stat.st_nlink < 2:
        return False
    places = [folder / name for name in records] if records else [folder]
    return any(_same_inode(found, stat) for place in places for found in _files(place))


def _same_inode(path: Path, stat: os.stat_result) -> bool:
    try:
        other = path.stat()
    except OSError:
        return False
    return (other.st_dev, other.st_ino) == (stat.st_dev, stat.st_ino)


def _files(place: Path) -> Iterable[Path]:
    if place.is_file():
        yield place
        return
    for root, _, names in os.walk(place):
        for name in names:
            yield Path(root) / name


def as_path(name: str, value: Any) -> Path:
    """``value`` as a Path if it is a non-empty text or path (``os.PathLike``).

    Raises:
        MimicsError: one line naming ``name`` and what was given.
    """
    if isinstance(value, str | os.PathLike) and not isinstance(value, bytes):
        text = os.fspath(value)
        if isinstance(text, str) and text.strip() and "\0" not in text:
            return Path(text)
    shown = repr(value) if len(repr(value)) <= 60 else repr(value)[:57] + "..."
    raise MimicsError(f"{name}: expected a path (a non-empty str or pathlib.Path), got {shown} "
                      f"(a {type(value).__name__})")
