"""A table written as a whole file at the end equals one part renamed (parts.py)."""

from __future__ import annotations

from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from mimics.records.parts import PartWriter

SCHEMA = pa.schema([("a", pa.int32()), ("b", pa.float64())])


def table(start: int, rows: int) -> pa.Table:
    return pa.table({"a": pa.array(range(start, start + rows), pa.int32()),
                     "b": pa.array([0.5 * i for i in range(rows)], pa.float64())}, schema=SCHEMA)


def test_a_last_lone_table_is_the_same_file_as_a_part_renamed(tmp_path: Path) -> None:
    as_part = PartWriter(tmp_path / "one.parts", SCHEMA)
    as_part.write(table(0, 50))
    assert as_part.merge(tmp_path / "one.parquet") == 50
    direct = PartWriter(tmp_path / "two.parts", SCHEMA)
    direct.write(table(0, 50), last=True)
    assert not (tmp_path / "two.parts").exists()  # held, no parts folder
    assert direct.merge(tmp_path / "two.parquet") == 50
    assert (tmp_path / "one.parquet").read_bytes() == (tmp_path / "two.parquet").read_bytes()
    assert not (tmp_path / "one.parts").exists() and not (tmp_path / "two.parts").exists()


def test_last_after_parts_is_written_as_a_part(tmp_path: Path) -> None:
    writer = PartWriter(tmp_path / "t.parts", SCHEMA)
    writer.write(table(0, 3))
    writer.write(table(3, 2), last=True)
    assert writer.parts == 2
    assert writer.merge(tmp_path / "t.parquet") == 5
    assert pq.read_table(tmp_path / "t.parquet")["a"].to_pylist() == [0, 1, 2, 3, 4]


def test_a_table_after_a_held_one_keeps_the_order(tmp_path: Path) -> None:
    writer = PartWriter(tmp_path / "t.parts", SCHEMA)
    writer.write(table(0, 2), last=True)
    writer.write(table(2, 2))
    assert writer.parts == 2
    assert writer.merge(tmp_path / "t.parquet") == 4
    assert pq.read_table(tmp_path / "t.parquet")["a"].to_pylist() == [0, 1, 2, 3]


def test_parts_found_on_disk_are_merged_not_replaced(tmp_path: Path) -> None:
    earlier = PartWriter(tmp_path / "old.parts", SCHEMA)
    earlier.write(table(0, 4))
    (tmp_path / "t.parts").mkdir()
    (tmp_path / "old.parts" / "part-000000.parquet").rename(
        tmp_path / "t.parts" / "part-000009.parquet")  # a part this writer did not write
    later = PartWriter(tmp_path / "t.parts", SCHEMA)
    later.write(table(4, 1), last=True)  # parts on disk: not held
    assert later.merge(tmp_path / "t.parquet") == 5
