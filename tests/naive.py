"""Slow, obvious references for the compiled geometry kernels (STYLE item 5).

No grid, no early exit, no Numba: every beam against every segment and every
robot edge, every robot against every wall and every other robot.

- Ray casting restates the kernel's *definition* of a hit (the same
  collinear/parallel thresholds, so both agree even on degenerate inputs);
  what the comparison checks is the grid walk: that the kernel tests every
  segment that matters. ``test_ranger.py`` checks this reference itself
  against shapely on generic inputs.
- Collisions use a different method from the kernel (orientation predicates
  and point-in-polygon on the corners, no tolerance, instead of separating
  axes and clipping in the robot's frame); ``test_collision.py`` compares both
  with shapely.
"""

from __future__ import annotations

import math

import numpy as np

PARALLEL_EPS = 1e-12
COLLINEAR_EPS = 1e-10

Point = tuple[float, float]


def robot_corners(cx: float, cy: float, heading: float, half_length: float,
                  half_width: float) -> list[Point]:
    """Front-left, rear-left, rear-right, front-right corners (counter-clockwise)."""
    c, s = math.cos(heading), math.sin(heading)
    ux, uy = half_length * c, half_length * s
    vx, vy = -half_width * s, half_width * c
    return [(cx + ux + vx, cy + uy + vy), (cx - ux + vx, cy - uy + vy),
            (cx - ux - vx, cy - uy - vy), (cx + ux - vx, cy + uy - vy)]


def robot_edges(cx: float, cy: float, heading: float, half_length: float,
                half_width: float) -> list[tuple[float, float, float, float]]:
    """The four sides as ``(x1, y1, x2, y2)``: left, rear, right, front."""
    p = robot_corners(cx, cy, heading, half_length, half_width)
    return [(*p[k], *p[(k + 1) % 4]) for k in range(4)]


# -- rays ---------------------------------------------------------------------------


def ray_hit(o: Point, d: Point, seg: tuple[float, float, float, float]) -> float:
    """Distance along the unit ray to the segment (nearer end when collinear); inf if none."""
    ox, oy = o
    dx, dy = d
    x1, y1, x2, y2 = (float(v) for v in seg)
    ex, ey = x2 - x1, y2 - y1
    wx, wy = x1 - ox, y1 - oy
    cross_de = dx * ey - dy * ex
    cross_we = wx * ey - wy * ex
    cross_wd = wx * dy - wy * dx
    if abs(cross_de) > PARALLEL_EPS * (abs(ex) + abs(ey)):
        sign = 1.0 if cross_de > 0 else -1.0
        den, nt, nu = sign * cross_de, sign * cross_we, sign * cross_wd
        inside = nt >= 0 and 0 <= nu <= den
        return nt / den if inside else math.inf
    on_line = abs(cross_wd) <= COLLINEAR_EPS and abs(cross_wd - cross_de) <= COLLINEAR_EPS
    if not on_line:
        return math.inf
    ends = [wx * dx + wy * dy, (x2 - ox) * dx + (y2 - oy) * dy]
    if max(ends) < 0:
        return math.inf
    return max(min(ends), 0.0)


def cast_rays(origins: np.ndarray, headings: np.ndarray, offsets: np.ndarray,
              max_range: np.ndarray, robot: np.ndarray, walls: np.ndarray,
              centers: np.ndarray, robot_headings: np.ndarray, half_length: np.ndarray,
              half_width: np.ndarray, solid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Reference ``cast_rays``: ``(ranges, hit_owner)`` with the same conventions."""
    targets: list[tuple[int, tuple[float, float, float, float]]] = [
        (-1, tuple(w)) for w in np.asarray(walls, dtype=float).reshape(-1, 4)]
    for j in range(len(centers)):
        if solid[j]:
            edges = robot_edges(centers[j, 0], centers[j, 1], robot_headings[j],
                                half_length[j], half_width[j])
            targets += [(j, e) for e in edges]
    k, beams = offsets.shape
    ranges = np.full((k, beams), np.nan)
    owner = np.full((k, beams), -2, dtype=np.int64)
    # a beam's direction as RangerQuery defines it: the heading's unit vector rotated by the
    # offset's (cosines and sines of the whole array, as the ranger takes them), not
    # (cos, sin) of the summed angle, whose last bits differ: two edges on one line (robots
    # stacked on one spot) are then a tie one way and 1 ulp apart the other
    cos_o, sin_o = np.cos(offsets), np.sin(offsets)
    for i in range(k):
        ch, sh = math.cos(headings[i]), math.sin(headings[i])
        for b in range(beams):
            if math.isnan(offsets[i, b]):
                continue
            co, so = float(cos_o[i, b]), float(sin_o[i, b])
            d = (ch * co - sh * so, sh * co + ch * so)
            best = (math.inf, -2)
            for who, seg in targets:
                if who >= 0 and who == robot[i]:
                    continue
                t = ray_hit((origins[i, 0], origins[i, 1]), d, seg)
                if t <= max_range[i]:
                    best = min(best, (t, who))
            ranges[i, b] = max_range[i] if best[1] == -2 else best[0]
            owner[i, b] = best[1]
    return ranges, owner


# -- collisions ----------------------------------------------------------------------


def _orient(a: Point, b: Point, c: Point) -> float:
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def _within_box(a: Point, b: Point, p: Point) -> bool:
    return (min(a[0], b[0]) <= p[0] <= max(a[0], b[0])
            and min(a[1], b[1]) <= p[1] <= max(a[1], b[1]))


def segments_intersect(p1: Point, p2: Point, q1: Point, q2: Point) -> bool:
    """Closed segments share a point (orientation test with the collinear cases)."""
    d1, d2 = _orient(q1, q2, p1), _orient(q1, q2, p2)
    d3, d4 = _orient(p1, p2, q1), _orient(p1, p2, q2)
    if ((d1 > 0 > d2) or (d1 < 0 < d2)) and ((d3 > 0 > d4) or (d3 < 0 < d4)):
        return True
    return ((d1 == 0 and _within_box(q1, q2, p1)) or (d2 == 0 and _within_box(q1, q2, p2))
            or (d3 == 0 and _within_box(p1, p2, q1)) or (d4 == 0 and _within_box(p1, p2, q2)))


def inside_convex(p: Point, corners: list[Point]) -> bool:
    """``p`` in the closed counter-clockwise convex polygon."""
    return all(_orient(corners[k], corners[(k + 1) % len(corners)], p) >= 0
               for k in range(len(corners)))


def segment_touches_rect(seg: tuple[float, float, float, float], corners: list[Point]) -> bool:
    """A segment crosses a side of the rectangle or lies inside it."""
    p, q = (seg[0], seg[1]), (seg[2], seg[3])
    if inside_convex(p, corners) or inside_convex(q, corners):
        return True
    return any(segments_intersect(p, q, corners[k], corners[(k + 1) % 4]) for k in range(4))


def rects_touch(a: list[Point], b: list[Point]) -> bool:
    """Two rectangles' sides cross, or one holds a corner of the other."""
    if any(inside_convex(p, b) for p in a) or any(inside_convex(p, a) for p in b):
        return True
    return any(segments_intersect(a[k], a[(k + 1) % 4], b[m], b[(m + 1) % 4])
               for k in range(4) for m in range(4))


def find_collisions(centers: np.ndarray, headings: np.ndarray, half_length: np.ndarray,
                    half_width: np.ndarray, check: np.ndarray, solid: np.ndarray,
                    walls: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Reference ``find_collisions``: ``(with_whom, wall_segment)``, same conventions."""
    n = len(centers)
    corners = [robot_corners(centers[i, 0], centers[i, 1], headings[i], half_length[i],
                             half_width[i]) for i in range(n)]
    walls = np.asarray(walls, dtype=float).reshape(-1, 4)
    with_whom = np.full(n, -2, dtype=np.int64)
    wall_segment = np.full(n, -1, dtype=np.int64)
    for i in range(n):
        if not check[i]:
            continue
        touching_walls = [k for k in range(len(walls))
                          if segment_touches_rect(tuple(walls[k]), corners[i])]
        touching_robots = [j for j in range(n)
                           if j != i and solid[j] and rects_touch(corners[i], corners[j])]
        wall_segment[i] = touching_walls[0] if touching_walls else -1
        if touching_robots:
            with_whom[i] = touching_robots[0]
        elif touching_walls:
            with_whom[i] = -1
    return with_whom, wall_segment
