"""Walls that no sensor in a cell can see first: dropped from the cell's near list.

A wall ``W`` is hidden from a cell by another wall ``O`` when every segment
from a point of the cell to a point of ``W`` crosses ``O``: then any beam
from the cell that reaches ``W`` meets ``O`` nearer, so ``W`` is never a
beam's nearest hit and the ranger need not sweep it. Dropping it changes no
range and no owner (walls all have the owner -1), only the work.

The test (one occluder at a time, so it is conservative: a wall hidden
only by several walls together stays listed) rests on convexity. For a
fixed ``p``, the points ``q`` with ``pq`` crossing ``O`` form a convex set
(the cone from ``p`` through ``O``, beyond ``O``'s line), and the same holds
with the roles swapped; so if the sight lines from the cell's four corners
to ``W``'s two ends all cross ``O``, every sight line from the cell to
``W`` does. With margins, so that rounding in the ranger cannot turn the
crossing into a miss:

- ``O`` is shortened by ``margin`` at both ends before the test, so every
  crossing lies at least that far inside ``O``;
- the cell lies wholly on one side of ``O``'s line and ``W`` on the other,
  each at least ``margin`` from it, so along any beam ``O``'s hit is at
  least ``margin`` nearer than ``W``'s;
- the cell is padded for the rounding of the sensor's cell lookup.

>>> import numpy as np
>>> walls = np.array([[2.0, -3.0, 2.0, 3.0], [4.0, -1.0, 4.0, 1.0], [4.0, 2.0, 4.0, 6.0]])
>>> cell = (0.0, 0.0, 1.0, 1.0)
>>> hidden_by_one(walls, 0, 1, cell), hidden_by_one(walls, 0, 2, cell)  # 2: seen over O's end
(True, False)
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from mimics.engine.compiling.kernel_minmax import larger, smaller
from mimics.engine.compiling.kernel_options import INNER

MARGIN = 1e-6  # m: how clearly a sight line must cross an occluder (rounding is far smaller)
PAD = 1e-9  # relative padding of a cell's box, for the rounding of the sensor's cell lookup


# rows of the occluders' array (one column per occluder: the first test runs along rows)
AX, AY, BX, BY, NX, NY = range(6)


@njit(**INNER)
def _corner(box: np.ndarray, k: int) -> tuple[float, float]:
    """Corner ``k`` (counterclockwise from the lowest) of the box ``(x0, y0, x1, y1)``."""
    return box[0] if k == 0 or k == 3 else box[2], box[1] if k < 2 else box[3]


@njit(**INNER)
def _crosses(px: float, py: float, qx: float, qy: float, occluders: np.ndarray,
             o: int) -> bool:
    """Whether occluder ``o``'s shortened ends lie clearly on either side of the line
    through ``p`` and ``q`` (their side of its own line is known)."""
    ex, ey = qx - px, qy - py
    # the ends' distances from the line, times its length: compared without a square root
    da = ex * (occluders[AY, o] - py) - ey * (occluders[AX, o] - px)
    db = ex * (occluders[BY, o] - py) - ey * (occluders[BX, o] - px)
    clear = 1e-9 * (abs(ex) + abs(ey))  # at least 1e-9 m (the length is at most |ex| + |ey|)
    return (da > clear and db < -clear) or (da < -clear and db > clear)


@njit(**INNER)
def _occluder(segments: np.ndarray, s: int, box: np.ndarray, margin: float,
              occluders: np.ndarray, o: int) -> None:
    """Fill column ``o`` with segment ``s`` shortened by ``margin`` at both ends and the
    unit normal of its line pointing away from the box; a zero normal (which passes no
    test) when it cannot occlude: too short, or its line passes within ``margin`` of
    the box."""
    ax, ay, bx, by = segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3]
    occluders[NX, o] = occluders[NY, o] = 0.0
    length = math.hypot(bx - ax, by - ay)
    if length <= 4.0 * margin:
        return
    ux, uy = (bx - ax) / length, (by - ay) / length
    nx, ny = -uy, ux
    low, high = math.inf, -math.inf
    for k in range(4):
        cx, cy = _corner(box, k)
        side = nx * (cx - ax) + ny * (cy - ay)
        low, high = smaller(low, side), larger(high, side)
    if low >= margin:  # the box on the normal's side: W must be on the other
        nx, ny = -nx, -ny
    elif high > -margin:
        return
    occluders[AX, o], occluders[AY, o] = ax + margin * ux, ay + margin * uy
    occluders[BX, o], occluders[BY, o] = bx - margin * ux, by - margin * uy
    occluders[NX, o], occluders[NY, o] = nx, ny


@njit(**INNER)
def _beyond(occluders: np.ndarray, o: int, margin: float, qx: float, qy: float) -> bool:
    """Whether ``q`` lies at least ``margin`` beyond occluder ``o``'s line, away from the box."""
    return (occluders[NX, o] * (qx - occluders[AX, o])
            + occluders[NY, o] * (qy - occluders[AY, o])) >= margin


@njit(**INNER)
def _sight_lines_cross(occluders: np.ndarray, o: int, box: np.ndarray, qx1: float,
                       qy1: float, qx2: float, qy2: float) -> bool:
    """Whether occluder ``o`` crosses the sight lines from the box's corners to both ends."""
    for k in range(4):
        cx, cy = _corner(box, k)
        if not (_crosses(cx, cy, qx1, qy1, occluders, o)
                and _crosses(cx, cy, qx2, qy2, occluders, o)):
            return False
    return True


@njit(cache=True)
def cull_hidden(segments: np.ndarray, origin: np.ndarray, shape: np.ndarray, cell: float,
                start: np.ndarray, items: np.ndarray, margin: float
                ) -> tuple[np.ndarray, np.ndarray]:
    """The CSR near lists ``(start, items)`` without the walls hidden from their cell.

    Each cell's walls are tried against the walls of its own list as
    occluders (any other wall that could hide one also lies within reach of
    the cell, nearer than it). Costs the square of a list's length: the
    first test (the wall beyond the occluder's line) runs over all occluders
    at once, without branches, and rules out most of them.
    """
    nx, ny = shape[0], shape[1]
    kept_start = np.zeros_like(start)
    kept = np.empty_like(items)
    longest = 0
    for c in range(nx * ny):
        longest = larger(longest, start[c + 1] - start[c])
    occluders = np.zeros((6, longest))
    beyond = np.empty(longest, dtype=np.bool_)
    box = np.empty(4)
    count = 0
    for c in range(nx * ny):
        x0, y0 = origin[0] + (c % nx) * cell, origin[1] + (c // nx) * cell
        pad = PAD * (1.0 + abs(x0) + abs(y0) + cell)
        box[0], box[1], box[2], box[3] = x0 - pad, y0 - pad, x0 + cell + pad, y0 + cell + pad
        listed = items[start[c]:start[c + 1]]
        walls = listed.shape[0]
        for o in range(walls):
            _occluder(segments, listed[o], box, margin, occluders, o)
        for w in range(walls):
            s = listed[w]
            qx1, qy1, qx2, qy2 = segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3]
            # a wall is never beyond its own line, so it never occludes itself
            for o in range(walls):
                beyond[o] = (_beyond(occluders, o, margin, qx1, qy1)
                             & _beyond(occluders, o, margin, qx2, qy2))
            hidden = False
            for o in range(walls):
                if beyond[o] and _sight_lines_cross(occluders, o, box, qx1, qy1, qx2, qy2):
                    hidden = True
                    break
            if not hidden:
                kept[count] = s
                count += 1
        kept_start[c + 1] = count
    return kept_start, kept[:count].copy()


def hidden_by_one(segments: np.ndarray, occluder: int, wall: int,
                  box: tuple[float, float, float, float], margin: float = MARGIN) -> bool:
    """Whether :func:`cull_hidden` drops wall ``segments[wall]`` from the square cell
    ``(x0, y0, x1, y1)`` whose list holds it and ``segments[occluder]`` (for tests and docs).
    """
    x0, y0, x1, y1 = box
    if not x1 - x0 == y1 - y0 > 0:
        raise ValueError(f"the cell must be a square, got {box}")
    _, kept = cull_hidden(np.ascontiguousarray(segments, dtype=np.float64),
                          np.array([x0, y0], dtype=np.float64), np.ones(2, np.int64),
                          float(x1 - x0), np.array([0, 2], np.int64),
                          np.array([occluder, wall], np.int64), margin)
    return wall not in kept.tolist()
