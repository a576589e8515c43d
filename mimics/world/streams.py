"""The named random streams of a run: one seed, an independent stream per purpose and robot.

Every random choice of a run comes from the run's seed through a stream named
by what it is for (``"ranger"``, ``"line.start_yaw"``...) and, where it
matters, by a robot's index. A stream's key is NumPy's ``SeedSequence(seed,
spawn_key=...)`` with the purpose's stable hash (BLAKE2b, the same on every
machine and Python) and the indices as spawn key: streams of different
purposes or robots are independent, and adding a robot, a sensor or a draw
to one stream leaves every other stream's draws as they were.

>>> a = stream(7, "line.start_yaw").uniform(size=3)
>>> b = stream(7, "line.start_yaw").uniform(size=3)
>>> c = stream(8, "line.start_yaw").uniform(size=3)
>>> bool((a == b).all()), bool((a == c).any())
(True, False)
>>> keyed_uniform(7, "jitter", 5)[:3].tolist() == keyed_uniform(7, "jitter", 3).tolist()
True
"""

from __future__ import annotations

import hashlib

import numpy as np

_GOLDEN = np.uint64(0x9E3779B97F4A7C15)  # SplitMix64's increment
_MIX1, _MIX2 = np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB)


def purpose_words(purpose: str) -> tuple[int, int]:
    """A purpose's stable key: two 32-bit words of its BLAKE2b hash (not Python's ``hash``,
    which changes between processes)."""
    digest = hashlib.blake2b(purpose.encode(), digest_size=8).digest()
    return int.from_bytes(digest[:4], "little"), int.from_bytes(digest[4:], "little")


def stream_seed(seed: int, purpose: str, *ids: int) -> np.random.SeedSequence:
    """The seed sequence of the stream ``(seed, purpose, *ids)``."""
    return np.random.SeedSequence(int(seed), spawn_key=(*purpose_words(purpose),
                                                        *(int(i) for i in ids)))


def stream(seed: int, purpose: str, *ids: int) -> np.random.Generator:
    """A generator for the stream ``(seed, purpose, *ids)`` (PCG64)."""
    return np.random.Generator(np.random.PCG64(stream_seed(seed, purpose, *ids)))


def _mix(z: np.ndarray) -> np.ndarray:
    """SplitMix64's finaliser, in place on a uint64 array."""
    z ^= z >> np.uint64(30)
    z *= _MIX1
    z ^= z >> np.uint64(27)
    z *= _MIX2
    z ^= z >> np.uint64(31)
    return z


def keyed_uniform(seed: int, purpose: str, count: int, low: float = 0.0,
                  high: float = 1.0) -> np.ndarray:
    """``count`` uniform draws in ``[low, high)``, draw ``i`` a function of ``(seed, purpose,
    i)`` only: robot i's value does not depend on how many robots there are.

    Counter-based (SplitMix64 of the stream's key plus ``i``), vectorised: a
    million robots' draws cost milliseconds, where a generator per robot would
    cost seconds.
    """
    key = stream_seed(seed, purpose).generate_state(1, np.uint64)[0]
    with np.errstate(over="ignore"):
        z = _mix(key + (np.arange(count, dtype=np.uint64) + np.uint64(1)) * _GOLDEN)
    unit = (z >> np.uint64(11)).astype(np.float64) * (1.0 / 2.0 ** 53)
    return low + (high - low) * unit


def keyed_normal(seed: int, purpose: str, count: int) -> np.ndarray:
    """``count`` standard normal draws, draw ``i`` a function of ``(seed, purpose, i)`` only
    (Box-Muller on two keyed uniforms)."""
    u1 = 1.0 - keyed_uniform(seed, f"{purpose}#radius", count)  # in (0, 1]: log is finite
    u2 = keyed_uniform(seed, f"{purpose}#angle", count)
    return np.sqrt(-2.0 * np.log(u1)) * np.cos(2.0 * np.pi * u2)
