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
from mimics.records.parts import PartWriter

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


class TrajectoryBuffer:
    """Buffers robot rows step by step and writes them through a :class:`PartWriter`.

    The rows go straight into the table's columns (arrays grown as needed, or
    sized once by :meth:`reserve`), so that the table at a flush is views of
    them: nothing is concatenated at the end of the run (about 10 ms of a
    100-robot Cave run's 60,000 rows, or of a Hospital run's 200,000).
    """

    def __init__(self, writer: PartWriter) -> None:
        self.writer = writer
        self.rows = 0  # rows buffered, not yet written
        self.steps = 0  # steps with at least one row, over the whole run
        self._last_step = -1
        self._reserve = 0  # rows to make room for at the next allocation
        # one row per column, pose as x, y, theta rows, and so on: see _allocate
        self._columns: dict[str, np.ndarray] = {}

    def reserve(self, rows: int) -> None:
        """Make room for ``rows`` rows at once when the buffer is next allocated (a
        hint: more are still taken, fewer leave the room unused, never touched)."""
        self._reserve = max(int(rows), 0)

    def add(self, state: WorldState, ids: np.ndarray) -> None:
        """Buffer the current rows of robots ``ids`` (sorted indices)."""
        count = ids.size
        if count == 0:
            return
        start, end = self.rows, self.rows + count
        columns = self._room(end)
        if count == state.n:  # every robot: the arrays as they are, without a gather
            columns["pose"][:, start:end] = state.pose.T
            columns["velocity"][:, start:end] = state.velocity.T
            columns["measured_pose"][:, start:end] = state.measured_pose.T
            columns["reference"][:, start:end] = state.reference.T
            columns["status"][start:end] = state.status
            columns["user_time"][start:end] = state.user_time
        else:
            for name in _BLOCK_ARRAYS:
                columns[name][..., start:end] = np.take(getattr(state, name).T, ids, axis=-1)
        columns["robot"][start:end] = ids
        columns["step"][start:end] = state.step
        columns["time"][start:end] = record_time(state.time)
        if state.step != self._last_step:
            self.steps += 1
            self._last_step = state.step
        self.rows = end

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
        # the table written is views of the columns, and the writer may keep it: the
        # next rows go into new ones
        self._columns = {}
        self.rows = 0

    def table(self) -> pa.Table | None:
        """The buffered rows as a table (None when there are none): views of the buffer."""
        if not self.rows:
            return None
        rows, columns = self.rows, self._columns
        pose, velocity = columns["pose"][:, :rows], columns["velocity"][:, :rows]
        measured, reference = columns["measured_pose"][:, :rows], columns["reference"][:, :rows]
        values = {
            "time": columns["time"][:rows], "step": columns["step"][:rows],
            "robot": columns["robot"][:rows],
            "x": pose[0], "y": pose[1], "theta": pose[2], "v": velocity[0], "w": velocity[1],
            "x_meas": measured[0], "y_meas": measured[1], "theta_meas": measured[2],
            "v_ref": reference[0], "heading_ref": reference[1],
            "status": columns["status"][:rows], "user_time": columns["user_time"][:rows],
        }
        arrays = [numeric_array(values[f.name], f.type) for f in TRAJECTORY_SCHEMA]
        return pa.Table.from_arrays(arrays, schema=TRAJECTORY_SCHEMA)

    def _room(self, rows: int) -> dict[str, np.ndarray]:
        """The columns, with room for ``rows`` rows (made or grown, the rows kept)."""
        columns = self._columns
        if columns and columns["time"].shape[-1] >= rows:
            return columns
        size = max(rows, self._reserve if not columns else 2 * columns["time"].shape[-1])
        grown = {name: np.empty((*shape, size), dtype) for name, (shape, dtype) in _COLUMNS.items()}
        for name, values in columns.items():
            grown[name][..., :self.rows] = values[..., :self.rows]
        self._columns = grown
        return grown


#: The buffer's arrays: leading shape and type (the table's types: int32 steps and robots,
#: int8 status, float32 user time; the engine's values cast as ``astype`` would).
_COLUMNS: dict[str, tuple[tuple[int, ...], type]] = {
    "pose": ((3,), np.float64), "velocity": ((2,), np.float64),
    "measured_pose": ((3,), np.float64), "reference": ((2,), np.float64),
    "status": ((), np.int8), "user_time": ((), np.float32), "robot": ((), np.int32),
    "step": ((), np.int32), "time": ((), np.float64),
}
