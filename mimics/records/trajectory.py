"""trajectory.parquet: every robot's state at every recorded step, streamed in parts.

A long table, one row per robot per recorded step, numbers only:

========== ======= ====================================================
column     type    meaning
========== ======= ====================================================
time       float64 simulated time of the step (s), rounded to 1e-9 s
step       int32   step number (0 is the initial state)
robot      int32   the engine's robot index, from 0
x, y       float64 true position (m)
theta      float64 true heading (rad)
v, w       float64 true speed (m/s) and turn rate (rad/s)
x_meas...  float64 ``x_meas``, ``y_meas``, ``theta_meas``: the positioning
                   sensor's (noisy) pose, as the robot's code saw it next
v_ref      float64 speed reference the robot's code returned (m/s)
heading_ref float64 heading reference the robot's code returned (rad)
status     int8    :class:`mimics.engine.state.Status` after the step
user_time  float32 seconds spent in the robot's code during the step
========== ======= ====================================================

Which rows: step 0 holds every robot; step k holds the robots that were
active at the start of step k, so a robot's last row is the step that
deactivated it, with its final status. Robots already deactivated are not
repeated (they do not move; a replay keeps their last row). With ``every`` > 1
only every ``every``-th step is recorded in full, plus the deactivation rows
and the final step. Rows of a step are in robot order (with ``every`` > 1 the
last step may come as two runs: robots deactivated in it, then the others).

Memory stays bounded: steps are buffered as blocks of arrays and written as a
part (one row group) every ``flush_rows`` rows or ``flush_seconds`` of wall
time, whichever comes first (:mod:`mimics.records.parts`).
"""

from __future__ import annotations

import numpy as np
import pyarrow as pa

from mimics.engine.state import WorldState
from mimics.records.arrow_columns import numeric_array
from mimics.records.parts import PartBuffer, PartWriter

TRAJECTORY_SCHEMA = pa.schema([
    ("time", pa.float64()), ("step", pa.int32()), ("robot", pa.int32()),
    ("x", pa.float64()), ("y", pa.float64()), ("theta", pa.float64()),
    ("v", pa.float64()), ("w", pa.float64()),
    ("x_meas", pa.float64()), ("y_meas", pa.float64()), ("theta_meas", pa.float64()),
    ("v_ref", pa.float64()), ("heading_ref", pa.float64()),
    ("status", pa.int8()), ("user_time", pa.float32()),
])

_BLOCK_ARRAYS = ("pose", "velocity", "measured_pose", "reference", "status", "user_time")


def record_time(time: float) -> float:
    """A simulated time as recorded: rounded to 1e-9 s (``0.1 * 3`` is stored as ``0.3``)."""
    return round(float(time), 9)


class TrajectoryBuffer(PartBuffer):
    """Buffers robot rows step by step and writes them through a :class:`PartWriter`."""

    def __init__(self, writer: PartWriter) -> None:
        super().__init__(writer)
        self.rows = 0  # rows buffered, not yet written
        self.steps = 0  # steps with at least one row, over the whole run
        self._last_step = -1
        self._times: list[float] = []
        self._steps: list[int] = []
        self._ids: list[np.ndarray] = []
        self._blocks: list[tuple[np.ndarray, ...]] = []

    def add(self, state: WorldState, ids: np.ndarray) -> None:
        """Buffer the current rows of robots ``ids`` (sorted indices)."""
        if ids.size == 0:
            return
        # Kept transposed, one row per column (pose as x, y, theta rows): the table's
        # columns are then contiguous rows of the concatenation, not strided copies.
        if ids.size == state.n:  # spelled out: the _BLOCK_ARRAYS, without a generator
            block = (state.pose.T.copy(), state.velocity.T.copy(), state.measured_pose.T.copy(),
                     state.reference.T.copy(), state.status.T.copy(), state.user_time.T.copy())
        else:
            block = tuple(np.take(getattr(state, name).T, ids, axis=-1) for name in _BLOCK_ARRAYS)
        if state.step != self._last_step:
            self.steps += 1
            self._last_step = state.step
        self._times.append(record_time(state.time))
        self._steps.append(state.step)
        self._ids.append(ids)
        self._blocks.append(block)
        self.rows += ids.size

    def _clear(self) -> None:
        self._times.clear()
        self._steps.clear()
        self._ids.clear()
        self._blocks.clear()
        self.rows = 0

    def table(self) -> pa.Table | None:
        """The buffered rows as a table (None when there are none)."""
        if not self.rows:
            return None
        counts = [ids.size for ids in self._ids]
        pose, velocity, measured, reference, status, user_time = (
            np.concatenate(column, axis=-1) for column in zip(*self._blocks, strict=True))
        columns = {
            "time": np.repeat(np.array(self._times), counts),
            "step": np.repeat(np.array(self._steps, dtype=np.int32), counts),
            "robot": np.concatenate(self._ids).astype(np.int32),
            "x": pose[0], "y": pose[1], "theta": pose[2], "v": velocity[0], "w": velocity[1],
            "x_meas": measured[0], "y_meas": measured[1], "theta_meas": measured[2],
            "v_ref": reference[0], "heading_ref": reference[1],
            "status": status.astype(np.int8, copy=False), "user_time": user_time.astype(np.float32),
        }
        arrays = [numeric_array(columns[f.name], f.type) for f in TRAJECTORY_SCHEMA]
        return pa.Table.from_arrays(arrays, schema=TRAJECTORY_SCHEMA)
