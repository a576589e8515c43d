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

The ranger, with far more draws a step than the other sensors (the Hospital's
360,000 beams), is counter-based instead (:class:`RangerNoise`): each beam's
draw is keyed by ``(seed, "ranger", step, robot, beam)`` and only beams that
hit something draw at all.

>>> streams = StepStreams(3, "position")
>>> first = streams.at(5).standard_normal(4)
>>> _ = streams.at(2).standard_normal(100)   # another step read in between...
>>> bool((streams.at(5).standard_normal(4) == first).all())   # ...changes nothing
True
"""

from __future__ import annotations

import numpy as np

from mimics.engine.ranging.ranger_noise import add_ranger_noise
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
    """The rangers' noise of a run: beam ``b`` of robot ``i`` at step ``k`` is a pure function
    of ``(seed, "ranger", k, i, b)`` (counter-based, :mod:`mimics.engine.ranging.ranger_noise`), so
    it depends on no other robot, beam, step or sensor; beams with no return get none."""

    def __init__(self, seed: int) -> None:
        self.key = int(stream_seed(seed, "ranger").generate_state(1, np.uint64)[0])

    def add(self, ranges: np.ndarray, hit_owner: np.ndarray, max_range: np.ndarray,
            sigma: np.ndarray, step: int, robots: np.ndarray) -> None:
        """Add step ``step``'s noise in place to the beams that hit of ``ranges`` (row ``r``:
        robot ``robots[r]``, noise ``sigma[r]``), clipped to ``[0, max_range]``."""
        add_ranger_noise(ranges, hit_owner, max_range, sigma, robots, self.key, step)


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
