"""Exact ray casting of range-finder beams against walls and robot edges.

Each beam walks the cells of the walls grid, then of the robots grid, along
its ray (Amanatides-Woo), and stops as soon as its best hit is no farther
than the exit of the cell it is in, so its cost depends on the segments near
it, not on the size of the map. Scanning robots run in parallel (``prange``);
every beam is computed from its own inputs only, so the results are the same
bit for bit whatever the number of threads.

The geometry (see :func:`ray_segment_distance`):

- a beam hits a segment where they cross, at distance ``t >= 0`` (an origin
  on a segment gives 0); a hit exactly at the maximum range counts;
- a segment collinear with the beam (within ``COLLINEAR_EPS`` m, at an angle
  below ``PARALLEL_EPS`` rad) is hit at its nearer end;
- the nearest hit wins; at equal distance the lower owner wins (a wall, -1,
  before any robot, and robot 2 before robot 5).

>>> import numpy as np
>>> from mimics.engine.spatial_index import build_segment_grid, empty_grid
>>> walls = build_segment_grid(np.array([[3.0, -1.0, 3.0, 1.0]]), (-5, -5, 5, 5))
>>> query = RangerQuery(np.zeros((1, 2)), np.zeros(1), np.array([[0.0, np.pi]]),
...                     np.array([8.0]), np.array([-1]))
>>> ranges, owner = cast_rays(query, walls, empty_grid())
>>> ranges.tolist(), owner.tolist()
([[3.0, 8.0]], [[-1, -2]])
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit, prange

from mimics.engine.spatial_index import SegmentGrid, coerce_array, coerce_grid

NO_HIT = -2  # hit_owner of a beam that hit nothing within range
WALL = -1  # hit_owner of a beam that hit a wall
PARALLEL_EPS = 1e-12  # |sin| of the beam-segment angle below which they are parallel
COLLINEAR_EPS = 1e-10  # a parallel segment this close to the beam's line lies on it (m)


class RangerQuery(NamedTuple):
    """The beams of ``k`` scanning robots.

    Attributes:
        origins: ``(k, 2)`` beam origins (robot centres).
        headings: ``(k,)`` headings (rad); a beam's angle is heading + offset.
        offsets: ``(k, B)`` beam angles relative to the heading; NaN marks an
            unused slot (robots of types with fewer beams).
        max_range: ``(k,)`` ranges (m).
        robot: ``(k,)`` int64 index of each scanning robot, whose own edges
            are skipped (-1 for a sensor that is not a robot).
    """

    origins: np.ndarray
    headings: np.ndarray
    offsets: np.ndarray
    max_range: np.ndarray
    robot: np.ndarray


@njit(cache=True)
def ray_segment_distance(ox: float, oy: float, dx: float, dy: float, x1: float, y1: float,
                         x2: float, y2: float) -> float:
    """Distance along the unit ray ``(ox, oy) + t (dx, dy)`` to a segment; inf if missed.

    Args:
        ox: ray origin x.
        oy: ray origin y.
        dx: unit direction x.
        dy: unit direction y.
        x1: first end x.
        y1: first end y.
        x2: second end x.
        y2: second end y.

    Returns:
        The smallest ``t >= 0`` on the segment, or ``inf``.
    """
    ex, ey = x2 - x1, y2 - y1
    wx, wy = x1 - ox, y1 - oy
    denom = dx * ey - dy * ex  # d x e
    num_t = wx * ey - wy * ex  # w x e
    num_u = wx * dy - wy * dx  # w x d: signed distance of the first end to the beam's line
    if abs(denom) > PARALLEL_EPS * (abs(ex) + abs(ey)):
        if denom < 0:
            denom, num_t, num_u = -denom, -num_t, -num_u
        # compare numerators: no division rounding in the inside/outside decision
        if num_t >= 0 and 0 <= num_u <= denom:
            return num_t / denom
        return math.inf
    # parallel (or a point): a hit only if both ends lie on the beam's line
    if abs(num_u) > COLLINEAR_EPS or abs(num_u - denom) > COLLINEAR_EPS:
        return math.inf
    tp = wx * dx + wy * dy
    tq = (x2 - ox) * dx + (y2 - oy) * dy
    near, far = min(tp, tq), max(tp, tq)
    if far < 0:
        return math.inf
    return max(near, 0.0)


@njit(cache=True)
def _trace(grid: SegmentGrid, ox: float, oy: float, dx: float, dy: float, limit: float,
           me: int, best_t: float, best_o: int) -> tuple[float, int]:
    """Improve ``(best_t, best_o)`` with the segments of ``grid`` hit within ``limit``."""
    if grid.segments.shape[0] == 0:
        return best_t, best_o
    gx, gy, c = grid.origin[0], grid.origin[1], grid.cell
    nx, ny = grid.shape[0], grid.shape[1]
    # clip the ray's [0, limit] to the grid box: it may start outside
    t0, t1 = 0.0, limit
    if dx != 0.0:
        ta, tb = (gx - ox) / dx, (gx + nx * c - ox) / dx
        t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
    elif ox < gx or ox > gx + nx * c:
        return best_t, best_o
    if dy != 0.0:
        ta, tb = (gy - oy) / dy, (gy + ny * c - oy) / dy
        t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
    elif oy < gy or oy > gy + ny * c:
        return best_t, best_o
    if t0 > t1:
        return best_t, best_o
    ix = int(min(max(math.floor((ox + t0 * dx - gx) / c), 0.0), nx - 1.0))
    iy = int(min(max(math.floor((oy + t0 * dy - gy) / c), 0.0), ny - 1.0))
    step_x = 1 if dx > 0 else -1
    step_y = 1 if dy > 0 else -1
    segs, owner = grid.segments, grid.owner
    for _ in range(nx + ny):  # a ray crosses at most nx + ny - 1 cells
        # exit distances recomputed from the cell index: no drift along long rays
        if dx > 0:
            tx = (gx + (ix + 1) * c - ox) / dx
        elif dx < 0:
            tx = (gx + ix * c - ox) / dx
        else:
            tx = math.inf
        if dy > 0:
            ty = (gy + (iy + 1) * c - oy) / dy
        elif dy < 0:
            ty = (gy + iy * c - oy) / dy
        else:
            ty = math.inf
        cid = iy * nx + ix
        for p in range(grid.cell_start[cid], grid.cell_start[cid + 1]):
            s = grid.cell_items[p]
            o = owner[s]
            if o >= 0 and o == me:
                continue
            t = ray_segment_distance(ox, oy, dx, dy, segs[s, 0], segs[s, 1], segs[s, 2],
                                     segs[s, 3])
            if t <= limit and (t < best_t or (t == best_t and o < best_o)):
                best_t, best_o = t, o
        t_exit = min(tx, ty)
        # farther cells only hold hits beyond t_exit (segments near a cell side
        # are listed on both sides of it, see grid_pad)
        if best_t <= t_exit or t_exit >= limit:
            break
        if tx < ty:
            ix += step_x
            if ix < 0 or ix >= nx:
                break
        else:
            iy += step_y
            if iy < 0 or iy >= ny:
                break
    return best_t, best_o


@njit(parallel=True, cache=True)
def _cast_kernel(query: RangerQuery, walls: SegmentGrid, robots: SegmentGrid,
                 ranges: np.ndarray, hit_owner: np.ndarray) -> None:
    """Fill ``ranges`` and ``hit_owner`` row by row (one scanning robot per row)."""
    k, beams = query.offsets.shape
    for i in prange(k):
        ox, oy = query.origins[i, 0], query.origins[i, 1]
        limit = query.max_range[i]
        me = query.robot[i]
        for j in range(beams):
            offset = query.offsets[i, j]
            if math.isnan(offset):
                ranges[i, j] = math.nan
                hit_owner[i, j] = NO_HIT
                continue
            angle = query.headings[i] + offset
            dx, dy = math.cos(angle), math.sin(angle)
            t, o = _trace(walls, ox, oy, dx, dy, limit, me, math.inf, NO_HIT)
            # robots only matter nearer than the nearest wall
            t, o = _trace(robots, ox, oy, dx, dy, min(limit, t), me, t, o)
            ranges[i, j] = limit if o == NO_HIT else t
            hit_owner[i, j] = o


def _as_query(query: RangerQuery) -> RangerQuery:
    offsets = coerce_array(query.offsets, np.float64, 2, "offsets")
    k = offsets.shape[0]
    q = RangerQuery(coerce_array(query.origins, np.float64, 2, "origins"),
                    coerce_array(query.headings, np.float64, 1, "headings"), offsets,
                    coerce_array(query.max_range, np.float64, 1, "max_range"),
                    coerce_array(query.robot, np.int64, 1, "robot"))
    if q.origins.shape != (k, 2) or any(len(a) != k for a in (q.headings, q.max_range, q.robot)):
        raise ValueError(f"query arrays disagree on the number of scanning robots ({k})")
    if not (np.all(np.isfinite(q.origins)) and np.all(np.isfinite(q.headings))):
        raise ValueError("beam origins and headings must be finite")
    if np.isinf(q.offsets).any():
        raise ValueError("beam offsets must be finite (or NaN for an unused slot)")
    if not np.all(q.max_range >= 0):
        raise ValueError("max_range must be >= 0")
    return q


def cast_rays(query: RangerQuery, walls: SegmentGrid,
              robots: SegmentGrid | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Trace every beam to its nearest wall or other robot's edge.

    Args:
        query: the beams (see :class:`RangerQuery`).
        walls: grid of wall segments (``build_segment_grid``).
        robots: grid of robot edges (``build_robot_grid``, built from the
            same poses), or None for no robots.

    Returns:
        ``ranges (k, B)``: distance to the nearest hit, ``max_range`` when
        nothing is hit within range, NaN in unused slots; ``hit_owner (k, B)``
        int64: -2 no hit (or unused slot), -1 a wall, ``j >= 0`` robot ``j``.

    Raises:
        ValueError: mismatched shapes, non-finite origins, headings or
            offsets, or a negative (or NaN) range.
    """
    q = _as_query(query)
    k, beams = q.offsets.shape
    ranges = np.empty((k, beams))
    hit_owner = np.empty((k, beams), dtype=np.int64)
    if k and beams:
        _cast_kernel(q, coerce_grid(walls), coerce_grid(robots), ranges, hit_owner)
    return ranges, hit_owner
