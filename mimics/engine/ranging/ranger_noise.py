"""The ranger's noise, counter-based: beam ``b`` of robot ``i`` at step ``k`` draws from
a generator of its own, keyed by ``(seed, "ranger", k, i, b)``.

Only beams that hit something get noise: a beam with no return (nothing
within range, ``hit_owner == -2``) reads exactly the maximum range, as real
lidars report "no return" rather than a phantom obstacle just short of it.
A hit's reading becomes ``clip(r + sigma * z, 0, range)``.

The draw ``z`` is a pure function of its key, so it does not depend on which
robots scan, which steps were read, other sensors or robots added after
``i`` (common random numbers, docs/explanation/determinism.md). The beam's
first word is

    w0 = mix(mix(mix(key + (k + 1) G) + (i + 1) G) + (b + 1) G)

(``key``: the first word of ``stream_seed(seed, "ranger")``, ``G`` the
golden-ratio increment, ``mix`` SplitMix64's finaliser (Steele et al. 2014),
all modulo 2**64); the rare draw that needs more words takes them from a
SplitMix64 generator started at ``w0``: ``mix(w0 + j G)``, j = 1, 2...
(started at the mixed word, not at the sum, so that they are not the next
beam's). ``z`` comes from those
words by the 256-layer ziggurat (Marsaglia and Tsang 2000, NumPy's layout): one
word and a table look-up for 99% of the beams, more words only in a wedge or
the tail.

The kernel works a row at a time in two passes, the same bits as one beam
at a time: the first computes every beam's first word and rectangle draw
without a branch, so that the compiler runs it over eight beams at once
(AVX-512 here), and flags the beams that hit but fall outside the
rectangles; the second draws those few through the whole ziggurat. Rows go
in chunks to the calling thread and a helper thread
(:mod:`mimics.engine.helper_threads`), as the ray kernel's do. On one thread
the Hospital's 360,000 beams take 0.77 to 0.88 ms (1.10 to 1.13 ms one beam at a
time) and the Cave's 18,000 0.043 to 0.045 ms (0.061 ms): benchmarks/NOTES.md.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.helper_threads.chunks import LEAD, begin_run, end_run, next_chunk
from mimics.engine.helper_threads.threads import helpers, helpers_worth, solo_arrays

GOLDEN = np.uint64(0x9E3779B97F4A7C15)  # SplitMix64's increment
MIX1, MIX2 = np.uint64(0xBF58476D1CE4E5B9), np.uint64(0x94D049BB133111EB)
NO_RETURN = -2  # hit_owner of a beam that hit nothing (ranger.py)

LAYERS = 256
TAIL = 3.6541528853610088  # where the base layer's tail starts (NumPy's ziggurat_nor_r)
LAYER_AREA = 0.00492867323399  # each layer's area under exp(-x**2 / 2)
_SCALE = 2.0 ** 52  # the 52 bits of a word that give a point's abscissa


def ziggurat_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(inner, width, height)`` per layer: a word's 52 bits ``a`` give ``x = a * width``,
    inside the curve at once when ``a < inner``; ``height[i]`` is ``exp(-x_i**2 / 2)`` at
    layer ``i``'s right edge ``x_i`` (layer 0: the base and its tail; 1: the top)."""
    inner = np.zeros(LAYERS, dtype=np.int64)
    width, height = np.zeros(LAYERS), np.zeros(LAYERS)
    edge = previous = TAIL
    base = LAYER_AREA / math.exp(-0.5 * edge * edge)  # the base rectangle's width
    inner[0] = int(edge / base * _SCALE)
    width[0], width[-1] = base / _SCALE, edge / _SCALE
    height[0], height[-1] = 1.0, math.exp(-0.5 * edge * edge)
    for i in range(LAYERS - 2, 0, -1):
        edge = math.sqrt(-2.0 * math.log(LAYER_AREA / edge + math.exp(-0.5 * edge * edge)))
        inner[i + 1] = int(edge / previous * _SCALE)
        previous = edge
        height[i], width[i] = math.exp(-0.5 * edge * edge), edge / _SCALE
    return inner, width, height


INNER, WIDTH, HEIGHT = ziggurat_tables()


@njit(cache=True, inline="always")
def _mix(z: np.uint64) -> np.uint64:  # pragma: no cover - compiled
    z = (z ^ (z >> np.uint64(30))) * MIX1
    z = (z ^ (z >> np.uint64(27))) * MIX2
    return z ^ (z >> np.uint64(31))


@njit(cache=True, inline="always")
def _unit(word: np.uint64) -> float:  # pragma: no cover - compiled
    """A word's top 53 bits as a double in [0, 1)."""
    return float(np.int64(word >> np.uint64(11))) * (1.0 / 9007199254740992.0)


@njit(cache=True, inline="always")
def _normal(state: np.uint64) -> float:  # pragma: no cover - compiled
    """The standard normal of the beam whose first word is ``mix(state)`` (the ziggurat;
    its tables are compiled in as constants: no arrays passed, no reference counts a
    call)."""
    word = _mix(state)
    state = word  # the further words: a generator started at the first
    while True:
        layer = np.int64(word & np.uint64(0xFF))
        negative = (word >> np.uint64(8)) & np.uint64(1)
        bits = np.int64((word >> np.uint64(9)) & np.uint64(0xFFFFFFFFFFFFF))
        x = float(bits) * WIDTH[layer]  # (52 bits: a signed conversion, the fast one)
        if bits < INNER[layer]:
            return -x if negative else x
        if layer == 0:  # the tail beyond TAIL, by Marsaglia's exponential rejection
            while True:
                state += GOLDEN
                xx = -math.log1p(-_unit(_mix(state))) / TAIL
                state += GOLDEN
                yy = -math.log1p(-_unit(_mix(state)))
                if yy + yy > xx * xx:
                    return -(TAIL + xx) if negative else TAIL + xx
        state += GOLDEN
        level = HEIGHT[layer] + _unit(_mix(state)) * (HEIGHT[layer - 1] - HEIGHT[layer])
        if level < math.exp(-0.5 * x * x):
            return -x if negative else x
        state += GOLDEN
        word = _mix(state)


# rows per chunk, the unit the calling thread and a helper take in turn (about 5 us)
CHUNK_ROWS = 16
# beams below which a call runs on the calling thread alone: a chunk handed to a helper
# that is asleep (40 to 70 us to wake, helper_threads) would wait longer than it takes
MIN_BEAMS_FOR_HELPER = 8192


@njit(cache=True, nogil=True)
def _add_noise(ranges: np.ndarray, hit_owner: np.ndarray, max_range: np.ndarray,
               sigma: np.ndarray, robots: np.ndarray, step_state: np.uint64,
               control: np.ndarray, share: np.ndarray, role: int,
               until: int) -> None:  # pragma: no cover - compiled
    """Add the noise to rows of ``ranges``, ``CHUNK_ROWS`` at a time, taking chunks with
    the helper threads that join (``helper_threads``, a ``run`` call); each row's draws
    depend on its own key only, so the bits are the same whichever thread takes it.

    A row in two passes. The first gives every beam its first word and the
    rectangles' draw without a branch, so that the compiler runs it over several
    beams at once (SIMD), and flags the beams that hit but fall outside the
    rectangles (1%), left as they are; the second draws those through the whole
    ziggurat (``_normal``). Both clip with the same operations, to the bit.
    """
    rows, beams = ranges.shape
    flags = np.zeros(beams, dtype=np.bool_)
    chunks = (rows + CHUNK_ROWS - 1) // CHUNK_ROWS
    begin_run(control, share, role)
    chunk = next_chunk(share)
    while chunk < chunks:
        for row in range(chunk * CHUNK_ROWS, smaller(rows, (chunk + 1) * CHUNK_ROWS)):
            spread, top = sigma[row], max_range[row]
            if spread == 0.0:  # a noise-free type in a mixed team
                continue
            robot_state = _mix(step_state + np.uint64(robots[row] + 1) * GOLDEN)
            reading, owner = ranges[row], hit_owner[row]
            flagged = 0
            for beam in range(beams):
                word = _mix(robot_state + np.uint64(beam + 1) * GOLDEN)
                layer = np.int64(word & np.uint64(0xFF))
                negative = (word >> np.uint64(8)) & np.uint64(1)
                bits = np.int64((word >> np.uint64(9)) & np.uint64(0xFFFFFFFFFFFFF))
                x = float(bits) * WIDTH[layer]
                z = -x if negative else x
                hit = owner[beam] != NO_RETURN
                inside = bits < INNER[layer]
                noisy = smaller(larger(reading[beam] + spread * z, 0.0), top)
                reading[beam] = noisy if hit and inside else reading[beam]
                flag = hit and not inside
                flags[beam] = flag
                flagged += flag
            beam = 0
            while flagged:  # (the flagged beams are about 2 a row)
                if flags[beam]:
                    z = _normal(robot_state + np.uint64(beam + 1) * GOLDEN)
                    reading[beam] = smaller(larger(reading[beam] + spread * z, 0.0), top)
                    flagged -= 1
                beam += 1
        chunk = next_chunk(share)
    end_run(share, role)


_WORD = (1 << 64) - 1


def _mix_int(z: int) -> int:
    """:func:`_mix` on a Python integer (no NumPy scalars: their overflow guard costs
    microseconds a call, more than the Cave's whole kernel saves)."""
    z = ((z ^ (z >> 30)) * int(MIX1)) & _WORD
    z = ((z ^ (z >> 27)) * int(MIX2)) & _WORD
    return z ^ (z >> 31)


def step_state(key: int, step: int) -> np.uint64:
    """The ranger's generator state of step ``step`` (``key``: the stream's first word)."""
    return np.uint64(_mix_int((key + (int(step) + 1) * int(GOLDEN)) & _WORD))


def add_ranger_noise(ranges: np.ndarray, hit_owner: np.ndarray, max_range: np.ndarray,
                     sigma: np.ndarray, robots: np.ndarray, key: int, step: int) -> None:
    """Add step ``step``'s noise to the beams of ``ranges`` that hit (``hit_owner`` not
    ``NO_RETURN``), in place, clipped to ``[0, max_range]``; row ``r`` is robot
    ``robots[r]``'s, with ``sigma[r]`` (0: left as it is). No-return beams and unused
    (NaN) slots are left as they are."""
    rows, beams = ranges.shape
    args = (ranges, hit_owner, np.ascontiguousarray(max_range, dtype=np.float64),
            np.ascontiguousarray(sigma, dtype=np.float64),
            np.ascontiguousarray(robots, dtype=np.int64), step_state(key, step))
    chunks = (rows + CHUNK_ROWS - 1) // CHUNK_ROWS
    helping = helpers_worth(min(chunks, rows * beams // MIN_BEAMS_FOR_HELPER))
    if helping:
        helpers(helping).run(_add_noise, args, chunks, helping)
    else:
        _add_noise(*args, *solo_arrays(chunks), LEAD, 0)
