"""The trajectory buffer: rows written into growing columns give the table that the rows,
taken one by one from the engine's arrays, make (whatever the room reserved)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from mimics.engine.state import WorldState
from mimics.records.parts import PartWriter
from mimics.records.trajectory import TRAJECTORY_SCHEMA, TrajectoryBuffer, record_time

from .helpers import box_scenario


def expected_rows(state: WorldState, ids: np.ndarray) -> list[dict[str, float]]:
    """The rows of robots ``ids``, one by one, as trajectory.parquet holds them."""
    return [{"time": record_time(state.time), "step": state.step, "robot": int(i),
             "x": state.pose[i, 0], "y": state.pose[i, 1], "theta": state.pose[i, 2],
             "v": state.velocity[i, 0], "w": state.velocity[i, 1],
             "x_meas": state.measured_pose[i, 0], "y_meas": state.measured_pose[i, 1],
             "theta_meas": state.measured_pose[i, 2], "v_ref": state.reference[i, 0],
             "heading_ref": state.reference[i, 1], "status": int(state.status[i]),
             "user_time": float(np.float32(state.user_time[i]))} for i in ids]


@pytest.mark.parametrize("reserve", [0, 1, 7, 1000])
def test_rows_of_steps_and_subsets_make_the_table(tmp_path: Path, reserve: int) -> None:
    scenario = box_scenario([[1 + k, 2, 0.1 * k, 0] for k in range(5)])
    state = WorldState.from_scenario(scenario, beams=1)
    rng = np.random.default_rng(4)
    buffer = TrajectoryBuffer(PartWriter(tmp_path / "parts", TRAJECTORY_SCHEMA))
    buffer.reserve(reserve)
    expected = []
    for step in range(9):
        state.step, state.time = step, step * 0.1
        for array in (state.pose, state.velocity, state.measured_pose, state.reference,
                      state.user_time):
            array[...] = rng.normal(size=array.shape)
        state.status[:] = rng.integers(0, 3, state.n)
        ids = np.arange(state.n) if step % 3 == 0 else np.flatnonzero(rng.random(state.n) < .5)
        buffer.add(state, ids)
        expected += expected_rows(state, ids)
    table = buffer.table()
    assert table is not None and table.schema == TRAJECTORY_SCHEMA
    assert table.to_pylist() == expected and buffer.rows == len(expected)
    buffer.flush()  # written, and the next rows go into new columns, the table kept whole
    assert buffer.rows == 0 and buffer.table() is None
    buffer.add(state, np.arange(state.n))
    assert table.to_pylist() == expected
    assert buffer.table().to_pylist() == expected_rows(state, np.arange(state.n))
