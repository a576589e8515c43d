"""events.parquet: what happened to which robot, and when, including messages.

One row per event:

=========== ======= ======================================================
column      type    meaning
=========== ======= ======================================================
time        float64 simulated time (s), rounded to 1e-9 s
step        int32   step at which it was recorded (rows of that step in
                    trajectory.parquet carry the same number)
robot       int32   the engine's robot index, from 0
kind        string  reached_goal, collision, escaped, deadlock, deadlock_end,
                    livelock, livelock_end, exception, user_message,
                    system_message, edit, edit_refused
detail      string  the engine's text ("Collision with robot 2", "Deadlock",
                    "Exception: ZeroDivisionError: division by zero"), the
                    message itself, or an edit's description ("add wall
                    segment [1, 0, 1, 2]") or refusal
other       int32   collisions: the robot hit, -1 for a wall; else -2
start       float64 deadlock and livelock: when the stall began; else NaN
traceback   string  exceptions: the user code's traceback (its frames only);
                    else empty
=========== ======= ======================================================

``edit`` rows are the edits of the world applied during the run
(``mimics.engine.edits``), at the step boundary they were applied at: the step
after which they apply, its time, the robot edited (-1 for a wall). A timed
edit of the scenario that the world refused then is an ``edit_refused`` row.

``user_message`` rows hold what a robot's code wrote with ``robot.log(...)``
during that step. The engine's system messages are the details of its events
joined by `` | ``, so they are not repeated; a ``system_message`` row appears
only for a system message that differs from those details.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pyarrow as pa

from mimics.engine.messages import filled
from mimics.engine.outcome import Event
from mimics.engine.state import WorldState
from mimics.records.arrow_columns import column_array
from mimics.records.parts import PartBuffer, PartWriter
from mimics.records.trajectory import record_time

EVENTS_SCHEMA = pa.schema([
    ("time", pa.float64()), ("step", pa.int32()), ("robot", pa.int32()),
    ("kind", pa.string()), ("detail", pa.string()), ("other", pa.int32()),
    ("start", pa.float64()), ("traceback", pa.string()),
])

STALL_KINDS = ("deadlock", "livelock")
MESSAGE_KINDS = ("user_message", "system_message")


class EventBuffer(PartBuffer):
    """Buffers event rows and writes them through a :class:`PartWriter`."""

    def __init__(self, writer: PartWriter) -> None:
        super().__init__(writer)
        self.rows: list[tuple[Any, ...]] = []
        self.counts: dict[str, int] = {}
        self._seen = 0  # engine events already taken

    def collect(self, events: list[Event], state: WorldState, ids: np.ndarray) -> None:
        """Take the engine's new events and the messages of robots ``ids`` this step.

        Args:
            events: the simulation's growing event list.
            state: the world state after the step.
            ids: robots that were active at the start of the step (sorted).
        """
        step, now = state.step, record_time(state.time)
        user = _messages(state.user_message, ids)
        for robot in user:
            self._add(now, step, robot, "user_message", state.user_message[robot])
        new = events[self._seen:]
        self._seen = len(events)
        details: dict[int, list[str]] = {}
        for event in new:
            start = event.start if math.isnan(event.start) else record_time(event.start)
            self._add(record_time(event.time), step, event.robot, event.kind, event.detail,
                      event.other, start, event.traceback)
            details.setdefault(event.robot, []).append(event.detail)
        for robot in _messages(state.system_message, ids):
            text = state.system_message[robot]
            if text != " | ".join(details.get(robot, ())):
                self._add(now, step, robot, "system_message", text)

    def _add(self, time: float, step: int, robot: int, kind: str, detail: str, other: int = -2,
             start: float = math.nan, traceback: str = "") -> None:
        self.rows.append((time, step, robot, kind, detail, other, start, traceback))
        self.counts[kind] = self.counts.get(kind, 0) + 1

    def _clear(self) -> None:
        self.rows.clear()

    def table(self) -> pa.Table | None:
        """The buffered rows as a table (None when there are none)."""
        if not self.rows:
            return None
        columns = list(zip(*self.rows, strict=True))
        arrays = [column_array(values, f.type)
                  for values, f in zip(columns, EVENTS_SCHEMA, strict=True)]
        return pa.Table.from_arrays(arrays, schema=EVENTS_SCHEMA)


def _messages(messages: list[str], ids: np.ndarray) -> list[int]:
    """Robots among ``ids`` (sorted, unique) with a non-empty message (the state's
    columns know them: most have none)."""
    candidates = filled(messages)
    if not candidates:
        return []
    if len(ids) == len(messages):  # every robot (the usual case)
        return candidates
    if not len(ids):
        return []
    found = np.asarray(candidates, dtype=np.int64)
    at = np.minimum(np.searchsorted(ids, found), len(ids) - 1)
    return found[ids[at] == found].tolist()
