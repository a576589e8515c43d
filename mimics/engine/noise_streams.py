"""The sensors' noise streams: per purpose, per step, rows by robot index.

Each noisy sensor draws from its own stream of the run's seed
(:func:`mimics.world.streams.stream_seed`, keyed ``"ranger"``, ``"position"``,
``"velocity"``, ``"acceleration"``, ``"odometry"``). Step ``k`` draws from its
own stretch of that stream, from ``2**64 * k`` on (far longer than any step
draws; reached by a jump, 1.6 us), so a step's noise is a function of the seed,
the sensor and the step alone: it does not depend on whether an earlier scan
was read, traced or skipped. Within a step the draws are laid out by robot
index, every robot's row whatever robots are active or scanning, so robot
``i``'s noise does not depend on which other robots scan, nor on robots added
after it; nor on any other sensor, nor on the algorithm's own draws
(``robot.rng``, a stream of its own). Two algorithms run with the same
scenario and seed thus meet the same noise on every sensor reading they take
(common random numbers); see docs/explanation/determinism.md.

>>> streams = StepStreams(3, "position")
>>> first = streams.at(5).standard_normal(4)
>>> _ = streams.at(2).standard_normal(100)   # another step read in between...
>>> bool((streams.at(5).standard_normal(4) == first).all())   # ...changes nothing
True
"""

from __future__ import annotations

import numpy as np

from mimics.world.streams import stream, stream_seed

NOISE_PURPOSES = ("ranger", "position", "velocity", "acceleration", "odometry")


class StepStreams:
    """One sensor's noise stream; :meth:`at` gives the generator of step ``k``'s stretch."""

    def __init__(self, seed: int, purpose: str) -> None:
        self._bits = np.random.PCG64(stream_seed(seed, purpose))
        self._start = self._bits.state
        self._rng = np.random.Generator(self._bits)

    def at(self, step: int) -> np.random.Generator:
        """The generator at the start of step ``step``'s stretch (the same object, moved)."""
        bits = self._bits
        bits.state = self._start
        bits.advance(int(step) << 64)  # (a NumPy integer would overflow the shift)
        return self._rng


class RangerNoise:
    """The rangers' standard normal draws of a step, one row per robot by index.

    Robots of one beam count (the usual case) draw a ``(rows, beams)`` block;
    mixed teams draw each robot's own beam count in turn, so that a robot's
    draws do not depend on the widest type of the team.
    """

    def __init__(self, seed: int, beam_count: np.ndarray, width: int) -> None:
        self._streams = StepStreams(seed, "ranger")
        counts = np.asarray(beam_count, dtype=np.int64)
        self._width = width
        self._same = bool(counts.size and counts.min() == counts.max() == width)
        self._ends = np.cumsum(counts)
        self._index = np.zeros((0, width), dtype=np.int64)
        if not self._same:  # a mixed team: where each robot's draws lie in the step's
            starts = self._ends - counts
            # padded slots (past a robot's beams) read any draw: their ranges are NaN
            last = max(int(self._ends[-1]) - 1, 0) if counts.size else 0
            self._index = np.minimum(starts[:, None] + np.arange(width), last)

    def draws(self, step: int, ids: np.ndarray | None) -> np.ndarray:
        """Step ``step``'s draws for robots ``ids`` (None: every robot), ``(rows, width)``."""
        rng = self._streams.at(step)
        rows = len(self._ends) if ids is None else int(ids[-1]) + 1  # ids are increasing
        if self._same:
            block = rng.standard_normal((rows, self._width))
            return block if ids is None else block[ids]
        flat = rng.standard_normal(int(self._ends[rows - 1]))
        return flat[self._index[:rows] if ids is None else self._index[ids]]


class AlgorithmStreams:
    """The algorithm's own generators (``robot.rng``): robot ``i``'s is the stream
    ``(seed, "algorithm", i)``, the team's ``(seed, "algorithm.team")``, each made on
    first use, so that one robot's draws shift neither another's nor any sensor's."""

    def __init__(self, seed: int) -> None:
        self._seed = seed
        self._made: dict[int | None, np.random.Generator] = {}

    def get(self, robot: int | None) -> np.random.Generator:
        """Robot ``robot``'s generator (None: the team's)."""
        key = None if robot is None else int(robot)
        rng = self._made.get(key)
        if rng is None:
            rng = self._made[key] = (stream(self._seed, "algorithm.team") if key is None
                                     else stream(self._seed, "algorithm", key))
        return rng
