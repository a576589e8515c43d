"""scans.parquet: the laser scans of a run, recorded on request, compactly.

Written only when asked (``mimics run ... --record-scans``,
``record_scans=True`` in :func:`mimics.simulate` and ``run_to_folder``,
``record_scans = true`` in a battery's ``[battery]`` table). One row per robot
per recorded step, for the robots whose ranger read the world at that step
(the scan their code sees at the next step):

====== ============== ===================================================
column type           meaning
====== ============== ===================================================
time   float64        simulated time of the step (s), as in trajectory.parquet
step   int32          step number (0 is the initial state)
robot  int32          the engine's robot index, from 0
ranges list<uint16>   each beam's distance in whole ``quantum`` steps
hits   list<bool>     whether the beam hit something (else nothing in range)
====== ============== ===================================================

**Quantisation.** A range ``r`` is stored as ``round(r / quantum)``; the
quantum is 1 mm (``0.001`` m) for rangers up to 65.535 m, and otherwise the
smallest whole number of millimetres that fits the longest range in 16 bits.
Read back, a range is within ``quantum / 2`` of the engine's value (0.5 mm
for every ranger in the library). Why not float16: its error grows with the
distance (up to 7.8 mm at 16-30 m for the Hokuyo), while millimetre steps
keep one bound everywhere, at the same two bytes a beam.

Rows are stored robot by robot (each robot's in step order) within each part
of the file (a row group, about 1300 steps of 100 robots): a robot's
consecutive scans are alike, so compression takes a quarter more off than
in step order. Sort by ``step`` when the order matters (:meth:`ScanRecord.robot`
does).

Which rows: the steps recorded in full in trajectory.parquet (every step, or
every ``every``-th, and the last), for the robots active after that step
(a deactivated robot's ranger stops). A row holds exactly as many beams as
its robot's type has. The beam angles (relative to the heading, right to
left), the range and the quantum are stored once per robot type in the
file's key-value metadata under ``mimics.scans`` (JSON), with each robot's
type, so that the file describes itself.

>>> import tempfile, mimics
>>> folder = tempfile.mkdtemp()
>>> _ = mimics.simulate("line", "go_to_goal", robots=2, time=1, seed=1, out=folder,
...                     record_scans=True)
>>> scans = mimics.load_run(folder).scans
>>> robot = scans.robot(1)
>>> robot.ranges.shape, scans.quantum, round(float(scans.angles(1)[-1]), 4)
((11, 270), 0.001, 2.3562)
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
import pyarrow as pa

from mimics.engine.state import WorldState
from mimics.records.arrow_columns import numeric_array
from mimics.records.parts import PartWriter
from mimics.records.trajectory import record_time
from mimics.world.errors import MimicsError
from mimics.world.scenario import Scenario

SCANS_SCHEMA = pa.schema([
    ("time", pa.float64()), ("step", pa.int32()), ("robot", pa.int32()),
    ("ranges", pa.list_(pa.uint16())), ("hits", pa.list_(pa.bool_())),
])
METADATA_KEY = b"mimics.scans"
MILLIMETRE = 0.001
_CODES = 65535  # the largest uint16


def range_quantum(longest_range: float) -> float:
    """The quantisation step (m) of a run whose longest ranger reaches ``longest_range`` m.

    >>> range_quantum(30.0), range_quantum(100.0)
    (0.001, 0.002)
    """
    millimetres = max(1, math.ceil(round(longest_range / MILLIMETRE, 6) / _CODES))
    return millimetres * MILLIMETRE


@dataclass(frozen=True)
class ScanLayout:
    """The beam geometry of a run's scans, once per robot type.

    Attributes:
        quantum: metres per stored unit; a read range is within ``quantum / 2``.
        type_names: the scenario's robot types, in order.
        angles: per type, its beam angles relative to the heading (rad).
        max_range: per type, its ranger's range (m).
        robot_type: ``(n,)`` each robot's index into the types.
    """

    quantum: float
    type_names: tuple[str, ...]
    angles: tuple[np.ndarray, ...]
    max_range: tuple[float, ...]
    robot_type: np.ndarray

    @classmethod
    def from_scenario(cls, scenario: Scenario) -> ScanLayout:
        """The layout of a scenario's scans."""
        ranges = tuple(float(t.ranger.range) for t in scenario.types)
        return cls(quantum=range_quantum(max(ranges, default=0.0)),
                   type_names=tuple(t.name for t in scenario.types),
                   angles=tuple(np.array(t.ranger.beam_offsets(), dtype=np.float64)
                                for t in scenario.types),
                   max_range=ranges, robot_type=np.asarray(scenario.type_index, dtype=np.int64))

    @property
    def beams(self) -> np.ndarray:
        """``(n,)`` each robot's number of beams."""
        counts = np.array([a.size for a in self.angles], dtype=np.int64)
        return counts[self.robot_type]

    def schema(self) -> pa.Schema:
        """:data:`SCANS_SCHEMA` carrying this layout as metadata."""
        data = {"quantum": self.quantum, "robot_type": self.robot_type.tolist(),
                "types": [{"name": name, "range": rng, "angles": angles.tolist()}
                          for name, rng, angles in zip(self.type_names, self.max_range,
                                                       self.angles, strict=True)]}
        return SCANS_SCHEMA.with_metadata({METADATA_KEY: json.dumps(data).encode()})

    @classmethod
    def from_metadata(cls, metadata: dict[bytes, bytes] | None, where: str) -> ScanLayout:
        """The layout stored in a scans file's metadata.

        Raises:
            MimicsError: naming ``where`` when the metadata is missing or malformed.
        """
        try:
            data = json.loads((metadata or {})[METADATA_KEY])
            types = data["types"]
            return cls(quantum=float(data["quantum"]),
                       type_names=tuple(str(t["name"]) for t in types),
                       angles=tuple(np.array(t["angles"], dtype=np.float64) for t in types),
                       max_range=tuple(float(t["range"]) for t in types),
                       robot_type=np.array(data["robot_type"], dtype=np.int64))
        except (KeyError, TypeError, ValueError) as exc:
            raise MimicsError(f"{where}: no readable {METADATA_KEY.decode()} metadata "
                              f"({type(exc).__name__}: {exc})") from None


def quantise(ranges: np.ndarray, quantum: float) -> np.ndarray:
    """Ranges (m, NaN for missing beams) as uint16 codes (0 for missing beams)."""
    codes = np.rint(np.nan_to_num(ranges, nan=0.0) / quantum)
    return np.clip(codes, 0, _CODES).astype(np.uint16)


class ScanBuffer:
    """Buffers robots' scans step by step and writes them through a :class:`PartWriter`."""

    def __init__(self, writer: PartWriter, layout: ScanLayout) -> None:
        self.writer = writer
        self.layout = layout
        self.rows = 0  # rows buffered, not yet written
        self._beams = layout.beams
        self._times: list[float] = []
        self._steps: list[int] = []
        self._ids: list[np.ndarray] = []
        self._codes: list[np.ndarray] = []
        self._hits: list[np.ndarray] = []

    def add(self, state: WorldState, ids: np.ndarray) -> None:
        """Buffer the current scans of robots ``ids`` (sorted indices; beamless ones dropped)."""
        ids = ids[self._beams[ids] > 0]
        if ids.size == 0:
            return
        every = ids.size == state.n
        scan = state.scan if every else state.scan[ids]
        hit = state.scan_hit if every else state.scan_hit[ids]
        self._times.append(record_time(state.time))
        self._steps.append(state.step)
        self._ids.append(ids)
        self._codes.append(quantise(scan, self.layout.quantum))
        self._hits.append(hit != -2)
        self.rows += ids.size

    def flush(self, table: pa.Table | None = None, last: bool = False) -> None:
        """Write the buffered rows as one part and empty the buffer (``last``: see
        :meth:`PartWriter.write`)."""
        table = table if table is not None else self.table()
        if table is None:
            return
        self.writer.write(table, last)
        for buffered in (self._times, self._steps, self._ids, self._codes, self._hits):
            buffered.clear()
        self.rows = 0

    def table(self) -> pa.Table | None:
        """The buffered rows as a table (None when there are none)."""
        if not self.rows:
            return None
        counts = [ids.size for ids in self._ids]
        times = np.repeat(np.array(self._times), counts)
        steps = np.repeat(np.array(self._steps, dtype=np.int32), counts)
        ids = np.concatenate(self._ids)
        # robot by robot: a robot's consecutive scans are alike, and zstd finds that
        # (302 -> 219 bytes a scan in the Cave), with the stored values unchanged
        order = np.lexsort((steps, ids))
        times, steps, ids = times[order], steps[order], ids[order]
        codes = np.concatenate(self._codes)[order]
        hits = np.concatenate(self._hits)[order]
        beams = self._beams[ids]
        if np.all(beams == codes.shape[1]):  # one beam count: the arrays as they are
            values, flags = codes.reshape(-1), hits.reshape(-1)
        else:  # keep each row's own beams
            keep = np.arange(codes.shape[1]) < beams[:, None]
            values, flags = codes[keep], hits[keep]
        offsets = numeric_array(np.concatenate([[0], np.cumsum(beams)]), pa.int32())
        arrays = [
            numeric_array(times, pa.float64()),
            numeric_array(steps, pa.int32()),
            numeric_array(ids, pa.int32()),
            pa.ListArray.from_arrays(offsets, numeric_array(values, pa.uint16())),
            pa.ListArray.from_arrays(offsets, numeric_array(flags, pa.bool_())),
        ]
        return pa.Table.from_arrays(arrays, schema=self.writer.schema)


class RobotScans(NamedTuple):
    """One robot's recorded scans, in step order."""

    steps: np.ndarray  # (k,) int
    times: np.ndarray  # (k,) s
    ranges: np.ndarray  # (k, beams) m, within quantum / 2 of the engine's
    hits: np.ndarray  # (k, beams) bool
    angles: np.ndarray  # (beams,) rad, relative to the heading
    max_range: float


class ScanRecord:
    """The scans of a run as read back (``mimics.load_run(folder).scans``).

    Attributes:
        table: the rows (``time``, ``step``, ``robot``, ``ranges`` codes, ``hits``).
        layout: beam angles, ranges and the quantum, per robot type.
    """

    def __init__(self, table: pa.Table, layout: ScanLayout) -> None:
        self.table = table
        self.layout = layout

    def __len__(self) -> int:
        return self.table.num_rows

    @property
    def quantum(self) -> float:
        """Metres per stored unit: a read range is within half of it of the engine's."""
        return self.layout.quantum

    def angles(self, robot: int) -> np.ndarray:
        """Robot ``robot``'s beam angles relative to its heading (rad, right to left)."""
        return self.layout.angles[int(self.layout.robot_type[robot])]

    def max_range(self, robot: int) -> float:
        """Robot ``robot``'s ranger range (m)."""
        return self.layout.max_range[int(self.layout.robot_type[robot])]

    def robot(self, robot: int) -> RobotScans:
        """Robot ``robot``'s scans, decoded to metres, in step order."""
        import pyarrow.compute as pc  # lazily: 60 ms to import
        rows = self.table.filter(pc.equal(self.table["robot"], robot))
        rows = rows.sort_by("step")
        shape = (rows.num_rows, self.angles(robot).size)
        return RobotScans(
            steps=rows["step"].to_numpy(), times=rows["time"].to_numpy(),
            ranges=decode(rows["ranges"], self.quantum).reshape(shape),
            hits=_flat(rows["hits"]).astype(bool).reshape(shape),
            angles=self.angles(robot), max_range=self.max_range(robot))


def decode(ranges: Any, quantum: float) -> np.ndarray:
    """The flat uint16 codes of a ``ranges`` list column, in metres (float64)."""
    return _flat(ranges).astype(np.float64) * quantum


def _flat(column: Any) -> np.ndarray:
    """The values of a (chunked) list column, concatenated."""
    chunks = column.chunks if isinstance(column, pa.ChunkedArray) else [column]
    parts = [chunk.flatten().to_numpy(zero_copy_only=False) for chunk in chunks]
    return np.concatenate(parts) if parts else np.zeros(0)
