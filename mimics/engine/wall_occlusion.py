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

MARGIN = 1e-6  # m: how clearly a sight line must cross an occluder (rounding is far smaller)
PAD = 1e-9  # relative padding of a cell's box, for the rounding of the sensor's cell lookup


@njit(cache=True, inline="always")
def _crosses(px: float, py: float, qx: float, qy: float, a: np.ndarray, o: int) -> bool:
    """Whether occluder ``o``'s shortened ends ``a[o, 0:2]``, ``a[o, 2:4]`` lie clearly on
    either side of the line through ``p`` and ``q`` (their side of its line is known).

    Whole arrays and an index, not a row: a row view per call costs more than the test.
    """
    ex, ey = qx - px, qy - py
    # the ends' distances from the line, times its length: compared without a square root
    da = ex * (a[o, 1] - py) - ey * (a[o, 0] - px)
    db = ex * (a[o, 3] - py) - ey * (a[o, 2] - px)
    clear = 1e-9 * (abs(ex) + abs(ey))  # at least 1e-9 m (the length is at most |ex| + |ey|)
    return (da > clear and db < -clear) or (da < -clear and db > clear)


@njit(cache=True)
def _occluder(segments: np.ndarray, s: int, box: np.ndarray, margin: float, out: np.ndarray,
              p: int) -> bool:
    """Fill ``out[p]`` with segment ``s`` shortened by ``margin`` at both ends and the unit
    normal of its line pointing away from the box; False if it cannot occlude (too short,
    or its line passes within ``margin`` of the box)."""
    ax, ay, bx, by = segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3]
    length = math.hypot(bx - ax, by - ay)
    if length <= 4.0 * margin:
        return False
    ux, uy = (bx - ax) / length, (by - ay) / length
    nx, ny = -uy, ux
    low, high = math.inf, -math.inf
    for k in range(4):
        cx = box[0] if k == 0 or k == 3 else box[2]
        cy = box[1] if k < 2 else box[3]
        side = nx * (cx - ax) + ny * (cy - ay)
        low, high = min(low, side), max(high, side)
    if low >= margin:  # the box on the normal's side: W must be on the other
        nx, ny = -nx, -ny
    elif high > -margin:
        return False
    out[p, 0], out[p, 1] = ax + margin * ux, ay + margin * uy
    out[p, 2], out[p, 3] = bx - margin * ux, by - margin * uy
    out[p, 4], out[p, 5] = nx, ny
    return True


@njit(cache=True, inline="always")
def _hides(occluders: np.ndarray, p: int, box: np.ndarray, margin: float, qx1: float,
           qy1: float, qx2: float, qy2: float) -> bool:
    """Whether occluder ``p`` (from :func:`_occluder`) hides the wall ``(q1, q2)`` from the box."""
    ox, oy, nx, ny = occluders[p, 0], occluders[p, 1], occluders[p, 4], occluders[p, 5]
    # the wall clearly beyond the occluder's line (cheap, and rules out most pairs)
    if nx * (qx1 - ox) + ny * (qy1 - oy) < margin or nx * (qx2 - ox) + ny * (qy2 - oy) < margin:
        return False
    for k in range(4):
        cx = box[0] if k == 0 or k == 3 else box[2]
        cy = box[1] if k < 2 else box[3]
        if not (_crosses(cx, cy, qx1, qy1, occluders, p)
                and _crosses(cx, cy, qx2, qy2, occluders, p)):
            return False
    return True


@njit(cache=True)
def cull_hidden(segments: np.ndarray, origin: np.ndarray, shape: np.ndarray, cell: float,
                start: np.ndarray, items: np.ndarray, margin: float
                ) -> tuple[np.ndarray, np.ndarray]:
    """The CSR near lists ``(start, items)`` without the walls hidden from their cell.

    Each cell's walls are tried against the walls of its own list as
    occluders (any other wall that could hide one also lies within reach of
    the cell, nearer than it). Costs the square of a list's length at worst:
    most pairs fail the first test.
    """
    nx, ny = shape[0], shape[1]
    kept_start = np.zeros_like(start)
    kept = np.empty_like(items)
    longest = 0
    for c in range(nx * ny):
        longest = max(longest, start[c + 1] - start[c])
    occluders = np.empty((longest, 6))
    usable = np.empty(longest, dtype=np.bool_)
    box = np.empty(4)
    count = 0
    for c in range(nx * ny):
        x0, y0 = origin[0] + (c % nx) * cell, origin[1] + (c // nx) * cell
        pad = PAD * (1.0 + abs(x0) + abs(y0) + cell)
        box[0], box[1], box[2], box[3] = x0 - pad, y0 - pad, x0 + cell + pad, y0 + cell + pad
        listed = items[start[c]:start[c + 1]]
        for p in range(listed.shape[0]):
            usable[p] = _occluder(segments, listed[p], box, margin, occluders, p)
        for w in range(listed.shape[0]):
            s = listed[w]
            qx1, qy1, qx2, qy2 = segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3]
            hidden = False
            for p in range(listed.shape[0]):
                if p != w and usable[p] and _hides(occluders, p, box, margin, qx1, qy1, qx2,
                                                   qy2):
                    hidden = True
                    break
            if not hidden:
                kept[count] = s
                count += 1
        kept_start[c + 1] = count
    return kept_start, kept[:count].copy()


def hidden_by_one(segments: np.ndarray, occluder: int, wall: int,
                  box: tuple[float, float, float, float], margin: float = MARGIN) -> bool:
    """Whether wall ``segments[wall]`` is hidden by ``segments[occluder]`` from the box
    ``(x0, y0, x1, y1)`` (the test :func:`cull_hidden` applies; for tests and docs)."""
    segs = np.ascontiguousarray(segments, dtype=np.float64)
    box_array = np.array(box, dtype=np.float64)
    found = np.empty((1, 6))
    if not _occluder(segs, occluder, box_array, margin, found, 0):
        return False
    q = segs[wall]
    return bool(_hides(found, 0, box_array, margin, q[0], q[1], q[2], q[3]))
