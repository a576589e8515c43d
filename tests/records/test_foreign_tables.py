"""A run folder whose Parquet files are valid but of another table is refused, naming the
file and the columns expected, by ``load_run``, ``mimics report`` and ``mimics plot``."""

from __future__ import annotations

import shutil
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mimics
from mimics.interfaces.cli import main
from mimics.records.trajectory import TRAJECTORY_SCHEMA
from mimics.world.errors import MimicsError
from tests.fuzzing import make_run_folder


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return make_run_folder(tmp_path_factory.mktemp("foreign") / "run")


def damaged(run: Path, target: Path, name: str, table: pa.Table) -> Path:
    shutil.copytree(run, target)
    pq.write_table(table, target / name)
    return target


def one_error(capsys: pytest.CaptureFixture[str], argv: list[str]) -> str:
    assert main(argv) == 2
    lines = [line for line in capsys.readouterr().err.splitlines() if line.strip()]
    assert len(lines) == 1, lines
    return lines[0]


def test_the_events_table_as_the_trajectory_is_refused_everywhere(
        run: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = damaged(run, tmp_path / "r", "trajectory.parquet",
                     pq.read_table(run / "events.parquet"))
    with pytest.raises(MimicsError, match=r"trajectory\.parquet: not the table expected here: "
                                          r"it has no column 'x' \(expected the columns time"):
        mimics.load_run(folder)
    for argv in (["report", str(folder)], ["plot", str(folder), "--out", str(tmp_path / "p.png")]):
        line = one_error(capsys, argv)
        assert "trajectory.parquet" in line and "x (double)" in line
    assert not (tmp_path / "p.png").exists()


# every way one column of the trajectory can be amiss: missing, retyped, doubled
COLUMN = st.sampled_from(TRAJECTORY_SCHEMA.names)
HOW = st.sampled_from(["drop", "string", "int64", "double"])


@settings(max_examples=12, deadline=None, derandomize=True)
@given(column=COLUMN, how=HOW)
def test_any_column_missing_or_of_another_type_is_named(
        run: Path, tmp_path_factory: pytest.TempPathFactory, column: str, how: str) -> None:
    table = pq.read_table(run / "trajectory.parquet")
    index = table.schema.get_field_index(column)
    if how == "drop":
        table = table.remove_column(index)
    else:
        kind = {"string": pa.string(), "int64": pa.int64(), "double": pa.float64()}[how]
        if TRAJECTORY_SCHEMA.field(column).type.equals(kind):
            table = table.append_column(column, table.column(index))  # a doubled column
        else:
            values = pa.array([str(v) for v in table.column(index).to_pylist()]) \
                if how == "string" else table.column(index).cast(kind, safe=False)
            table = table.set_column(index, column, values)
    folder = damaged(run, tmp_path_factory.mktemp("col") / "r", "trajectory.parquet", table)
    with pytest.raises(MimicsError) as error:
        mimics.load_run(folder)
    message = str(error.value)
    assert f"{column!r}" in message and "trajectory.parquet" in message and "\n" not in message


def test_a_run_with_its_own_tables_still_loads(run: Path) -> None:
    loaded = mimics.load_run(run)
    assert len(loaded.trajectory) == 12  # 2 robots x steps 0..5 (0.5 s at dt 0.1)
