"""Parquet tables written in complete parts while a run goes on, merged at its end.

A Parquet file is only readable once its footer is written, so a writer killed
midway leaves nothing usable. Instead, each flush of a recorder's buffer
becomes its own small file ``part-000000.parquet`` in a parts folder, written
under a ``.tmp`` name and renamed once complete: whatever happens to the
process, every ``part-*.parquet`` present is whole. When the run ends the parts
are merged, one row group each, into the single final file (a lone part is
just renamed) and the parts folder is removed. Readers prefer the final file
and fall back on the parts (a killed run).

>>> import tempfile, pyarrow as pa
>>> from pathlib import Path
>>> folder = Path(tempfile.mkdtemp())
>>> schema = pa.schema([("a", pa.int32())])
>>> writer = PartWriter(folder / "t.parts", schema)
>>> writer.write(pa.table({"a": pa.array([1, 2], pa.int32())}))
>>> writer.write(pa.table({"a": pa.array([3], pa.int32())}))
>>> writer.merge(folder / "t.parquet")
3
>>> read_table(folder / "t.parquet", folder / "t.parts", schema)["a"].to_pylist()
[1, 2, 3]
"""

from __future__ import annotations

import os
import shutil
from abc import ABC, abstractmethod
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pyarrow as pa
import pyarrow.parquet as pq

from mimics.records.arrow_columns import empty_table
from mimics.world.errors import MimicsError

COMPRESSION = "zstd"
_PART_GLOB = "part-*.parquet"
# the parts written are also kept in memory up to this many bytes, so that the merge
# does not read them back (a 600 s Cave run's trajectory: about 60 MB)
KEPT_BYTES = 128 * 1024 * 1024


class PartWriter:
    """Writes tables of one schema as complete part files, then merges them.

    Args:
        folder: the parts folder (created on the first write).
        schema: every table written must have exactly this schema.
        compression: Parquet codec of the parts and of the merged file.
    """

    def __init__(self, folder: Path, schema: pa.Schema, compression: str = COMPRESSION) -> None:
        self.folder = Path(folder)
        self.schema = schema
        self.compression = compression
        self.parts = 0
        self.rows = 0
        #: after ``merge(..., keep=True)`` of several parts: the merged table, else None
        self.merged: pa.Table | None = None
        self._last: pa.Table | None = None  # the whole table, held for merge (see write)
        self._kept: dict[Path, pa.Table] = {}  # parts written, while they fit KEPT_BYTES
        self._kept_bytes = 0

    def write(self, table: pa.Table, last: bool = False) -> None:
        """Write ``table`` as the next part (nothing for an empty table).

        ``last``: no other table comes before :meth:`merge`. When it is also the
        first, it is held and merge writes it straight as the final file: the same
        file as a lone part renamed, without a parts folder to make and remove.
        """
        if table.num_rows == 0:
            return
        if self._last is not None:  # a table after the last one: the held one goes first
            held, self._last = self._last, None
            self.write(held)
        if last and self.parts == 0 and not part_files(self.folder):
            self._last = table
            self.rows += table.num_rows
            return
        self.folder.mkdir(parents=True, exist_ok=True)
        path = self.folder / f"part-{self.parts:06d}.parquet"
        tmp = path.with_name(path.name + ".tmp")
        pq.write_table(table, tmp, row_group_size=table.num_rows, **self._options())
        os.replace(tmp, path)
        self.parts += 1
        self.rows += table.num_rows
        if self._kept_bytes + table.nbytes <= KEPT_BYTES:
            self._kept[path] = table
            self._kept_bytes += table.nbytes

    def merge(self, target: Path, keep: bool = False) -> int:
        """Merge every part into ``target`` (an empty table when none); returns its rows.

        With ``keep``, the parts read while merging several are kept in
        ``merged``, so that a caller needing the whole table does not read it back.
        """
        self.merged = None
        if self._last is not None:  # one table in all, never written as a part
            table, self._last = self._last, None
            tmp = target.with_name(target.name + ".tmp")
            pq.write_table(table, tmp, row_group_size=table.num_rows, **self._options())
            os.replace(tmp, target)
            return table.num_rows
        parts = part_files(self.folder)
        if len(parts) == 1:
            os.replace(parts[0], target)
            # a part this writer wrote holds its rows; one found on disk is read
            rows = self.rows if self.parts == 1 else pq.read_metadata(target).num_rows
        else:
            tmp = target.with_name(target.name + ".tmp")
            rows = 0
            kept = []
            with pq.ParquetWriter(tmp, self.schema, **self._options()) as writer:
                for part in parts:
                    table = self._kept.get(part)
                    if table is None:  # too big to keep, or found on disk
                        table = pq.read_table(part)
                    writer.write_table(table, row_group_size=max(table.num_rows, 1))
                    rows += table.num_rows
                    if keep:
                        kept.append(table)
            os.replace(tmp, target)
            if keep:
                self.merged = pa.concat_tables(kept) if kept else empty_table(self.schema)
        self._kept.clear()
        self._kept_bytes = 0
        shutil.rmtree(self.folder, ignore_errors=True)
        return rows

    def _options(self) -> dict[str, Any]:
        return {"compression": self.compression, "use_dictionary": _dictionary_columns(self.schema)}


class PartBuffer(ABC):
    """Rows held in memory and written through a :class:`PartWriter` as one part at a
    time: a subclass holds its rows its own way (:meth:`table`, :meth:`_clear`)."""

    def __init__(self, writer: PartWriter) -> None:
        self.writer = writer

    @abstractmethod
    def table(self) -> pa.Table | None:
        """The buffered rows as a table (None when there are none)."""

    @abstractmethod
    def _clear(self) -> None:
        """Forget the buffered rows (they have been written)."""

    def flush(self, table: pa.Table | None = None, last: bool = False) -> None:
        """Write the buffered rows as one part and empty the buffer.

        Args:
            table: the buffered rows when the caller already has them from :meth:`table`.
            last: no rows follow before the merge (see :meth:`PartWriter.write`).
        """
        table = table if table is not None else self.table()
        if table is None:
            return
        self.writer.write(table, last)
        self._clear()


def _dictionary_columns(schema: pa.Schema) -> list[str]:
    """Dictionary-encode integers and strings (few distinct values), never floats."""
    return [f.name for f in schema if not pa.types.is_floating(f.type)]


def part_files(folder: Path) -> list[Path]:
    """The complete part files of ``folder``, in order (none if it does not exist)."""
    return sorted(Path(folder).glob(_PART_GLOB)) if Path(folder).is_dir() else []


def one_line(exc: BaseException) -> str:
    """An exception's message on one line."""
    return " ".join(str(exc).split()) or type(exc).__name__


def check_readable(path: Path, schema: pa.Schema | None = None) -> None:
    """Read the footer of a Parquet file, raising a one-line error naming it.

    Args:
        path: the file.
        schema: the columns it must hold, each of its type (None: any).

    Raises:
        MimicsError: when the file is truncated or not Parquet, or (with ``schema``) is
            another table: a column missing or of another type.
    """
    try:
        found = pq.read_schema(path)
    except (pa.ArrowException, OSError, UnicodeError) as exc:
        raise MimicsError(f"{path}: not a readable Parquet file, truncated or corrupt "
                          f"({one_line(exc)})") from None
    if schema is not None:
        check_columns(path, found, schema)


def check_columns(path: Path, found: pa.Schema, schema: pa.Schema) -> None:
    """Refuse a Parquet file of another table: every column of ``schema`` must be in
    ``found`` with its type (a valid file of other columns would read as empty or wrong).

    Raises:
        MimicsError: naming the file, the first column amiss and the columns expected.
    """
    for column in schema:
        places = found.get_all_field_indices(column.name)
        if not places:
            problem = "has no column"
        elif len(places) > 1:
            problem = "has more than one column"
        elif not found.field(places[0]).type.equals(column.type):
            problem = f"has {found.field(places[0]).type} for column"
        else:
            continue
        expected = ", ".join(f"{c.name} ({c.type})" for c in schema)
        raise MimicsError(f"{path}: not the table expected here: it {problem} "
                          f"{column.name!r} (expected the columns {expected})")


def read_table(final: Path, parts: Path, schema: pa.Schema, columns: Sequence[str] | None = None,
               filters: Any = None) -> pa.Table:
    """The table in ``final``, else the concatenation of the complete parts in ``parts``.

    Args:
        final: the merged file of a finished run.
        parts: the parts folder a killed run leaves.
        schema: the table's schema (for an empty result).
        columns: columns to read (all by default).
        filters: a pyarrow filter expression or DNF list, applied while reading.

    Raises:
        MimicsError: naming the file, when one is truncated or not Parquet.
    """
    files = [final] if final.exists() else part_files(parts)
    names = list(columns) if columns is not None else schema.names
    tables = []
    for path in files:
        try:
            check_columns(path, pq.read_schema(path), schema)  # before: read as another table
            tables.append(pq.read_table(path, columns=names, filters=filters, schema=schema))
        except (pa.ArrowException, OSError, UnicodeError) as exc:
            raise MimicsError(f"{path}: not a readable Parquet file, truncated or corrupt "
                              f"({one_line(exc)})") from None
    if not tables:
        return empty_table(pa.schema([schema.field(n) for n in names]))
    return pa.concat_tables(tables) if len(tables) > 1 else tables[0]
