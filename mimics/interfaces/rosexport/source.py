"""What an export reads from a run folder, through :func:`mimics.records.run_folder.load_run`.

The trajectory comes as plain arrays sorted by step then robot (the order the
messages are written in), with each row's stamp in nanoseconds.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from mimics.interfaces.rosexport.conversion import stamps
from mimics.records.run_folder import Run

COLUMNS = ("time", "step", "robot", "x", "y", "theta", "v", "w", "x_meas", "y_meas", "theta_meas",
           "status")


@dataclass(frozen=True)
class Trajectory:
    """A run's trajectory rows as arrays, in (step, robot) order."""

    time: np.ndarray
    stamp: np.ndarray  # int64 nanoseconds
    step: np.ndarray
    robot: np.ndarray
    x: np.ndarray
    y: np.ndarray
    theta: np.ndarray
    v: np.ndarray
    w: np.ndarray
    x_meas: np.ndarray  # the positioning sensor's pose
    y_meas: np.ndarray
    theta_meas: np.ndarray
    status: np.ndarray

    @property
    def rows(self) -> int:
        """Number of rows."""
        return int(self.step.size)

    @classmethod
    def of(cls, run: Run) -> Trajectory:
        """The trajectory of ``run``."""
        table = run.read_trajectory(columns=list(COLUMNS), arrow=True)
        columns = {name: table[name].to_numpy() for name in COLUMNS}
        order = np.lexsort((columns["robot"], columns["step"]))
        columns = {name: np.ascontiguousarray(values[order]) for name, values in columns.items()}
        stamp = stamps(columns["time"])
        return cls(stamp=stamp, **columns)
