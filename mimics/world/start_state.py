"""The start state of a scenario: robots inside the bounds, clear of walls and of each other.

:func:`validate_scenario` runs on every scenario when it loads (a TOML file, a
Python file, a built-in), so a start in collision is reported before the run,
naming the robots and where they are; ``allow_overlap`` keeps it on purpose.

>>> from mimics.world.maps import Map
>>> from mimics.world.robot_types import PIONEER_2DX
>>> pair = Scenario.from_matrix([[0, 0, 0, 0], [0.2, 0, 0, 0]], Map.empty((-5, -5, 5, 5)),
...                             PIONEER_2DX)
>>> validate_scenario(pair, allow_overlap=True)
['robot 0 at (0, 0) and robot 1 at (0.2, 0) overlap at the start (expected them apart)']
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from mimics.world.errors import ScenarioError
from mimics.world.scenario import Scenario

TOUCH_EPS = 1e-9  # m; contact this close counts as touching, as in the engine's collision check


@dataclass(frozen=True)
class Bodies:
    """Robot rectangles: centres ``(n, 2)``, headings, half length (along heading), half width."""

    centers: np.ndarray
    headings: np.ndarray
    half_length: np.ndarray
    half_width: np.ndarray

    @classmethod
    def of(cls, scenario: Scenario) -> Bodies:
        """The rectangles of a scenario's robots at the start."""
        sizes = np.array([(t.length / 2, t.width / 2) for t in scenario.types])[
            scenario.type_index]
        return cls(scenario.stages[:, :2], scenario.stages[:, 2], sizes[:, 0], sizes[:, 1])

    @property
    def radius(self) -> np.ndarray:
        """Half diagonals: the reach of each rectangle from its centre."""
        return np.hypot(self.half_length, self.half_width)


def touching_walls(bodies: Bodies, segments: np.ndarray, grow: float = 0.0,
                   eps: float = TOUCH_EPS) -> tuple[np.ndarray, np.ndarray]:
    """Pairs ``(robot, segment)`` where a rectangle (grown by ``grow``) touches a segment.

    Exact: each candidate segment (its bounding box within the robot's reach, found
    through a grid: :func:`grid_candidates`) is clipped against the rectangle in the
    rectangle's frame (Liang-Barsky); a segment inside the rectangle touches it.
    Pairs come robot by robot, each robot's segments in order.
    """
    n, segments = len(bodies.centers), np.asarray(segments, dtype=np.float64).reshape(-1, 4)
    if n == 0 or len(segments) == 0:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    hx, hy = bodies.half_length + grow + eps, bodies.half_width + grow + eps
    reach = np.hypot(hx, hy)
    lo = np.minimum(segments[:, :2], segments[:, 2:])
    hi = np.maximum(segments[:, :2], segments[:, 2:])
    robots, segs = [np.zeros(0, np.int64)], [np.zeros(0, np.int64)]
    widest = float(reach.max())
    for j, i in grid_candidates(bodies.centers, lo - widest, hi + widest, 2 * widest):
        c, r = bodies.centers[i], reach[i]
        near = ((lo[j, 0] <= c[:, 0] + r) & (hi[j, 0] >= c[:, 0] - r)
                & (lo[j, 1] <= c[:, 1] + r) & (hi[j, 1] >= c[:, 1] - r))
        robots.append(i[near])
        segs.append(j[near])
    i, j = np.concatenate(robots), np.concatenate(segs)
    by_robot = np.lexsort((j, i))  # robot by robot, its walls in order
    i, j = i[by_robot], j[by_robot]
    cos, sin = np.cos(bodies.headings[i]), np.sin(bodies.headings[i])
    rel = segments[j] - np.tile(bodies.centers[i], 2)
    x1, y1 = rel[:, 0] * cos + rel[:, 1] * sin, -rel[:, 0] * sin + rel[:, 1] * cos
    x2, y2 = rel[:, 2] * cos + rel[:, 3] * sin, -rel[:, 2] * sin + rel[:, 3] * cos
    dx, dy = x2 - x1, y2 - y1
    t0, t1 = np.zeros(len(i)), np.ones(len(i))
    rejected = np.zeros(len(i), dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        for p, q in ((-dx, x1 + hx[i]), (dx, hx[i] - x1), (-dy, y1 + hy[i]), (dy, hy[i] - y1)):
            rejected |= (p == 0) & (q < 0)
            ratio = q / p
            t0 = np.where(p < 0, np.maximum(t0, ratio), t0)
            t1 = np.where(p > 0, np.minimum(t1, ratio), t1)
    hit = ~rejected & (t0 <= t1)
    return i[hit], j[hit]


def overlapping_robots(bodies: Bodies, eps: float = TOUCH_EPS) -> tuple[np.ndarray, np.ndarray]:
    """Pairs ``(i, j)``, ``i < j``, of robots whose rectangles touch (separating axis test).

    Candidates come from a grid (:func:`grid_candidates`), in chunks of about
    ``PAIR_CHUNK`` pairs, so that time grows with the robots (not their
    square: a packed swarm of 100,000 has a few candidates per robot) and
    memory stays bounded for millions of robots.
    """
    n = len(bodies.centers)
    if n < 2:
        return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
    radius = bodies.radius
    reach = radius + float(radius.max()) + eps  # a robot touching i is this near it
    found = [_touching_pairs(bodies, i[i < j], j[i < j], eps)
             for i, j in grid_candidates(bodies.centers, bodies.centers - reach[:, None],
                                         bodies.centers + reach[:, None], float(reach.max()))]
    pairs = np.concatenate(found) if found else np.zeros((0, 2), dtype=np.int64)
    pairs = pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))] if len(pairs) else pairs
    return pairs[:, 0], pairs[:, 1]


PAIR_CHUNK = 1_000_000  # candidate pairs tested at once (a few tens of MB of temporaries)


def _touching_pairs(bodies: Bodies, a: np.ndarray, b: np.ndarray, eps: float) -> np.ndarray:
    """The pairs ``(a[k], b[k])`` whose rectangles touch, each sorted (the test is symmetric)."""
    d = bodies.centers[b] - bodies.centers[a]
    close = np.hypot(d[:, 0], d[:, 1]) <= bodies.radius[a] + bodies.radius[b] + eps
    a, b, d = a[close], b[close], d[close]
    ca, sa = np.cos(bodies.headings[a]), np.sin(bodies.headings[a])
    cb, sb = np.cos(bodies.headings[b]), np.sin(bodies.headings[b])
    separated = np.zeros(len(a), dtype=bool)
    for ux, uy in ((ca, sa), (-sa, ca), (cb, sb), (-sb, cb)):
        extent_a = (bodies.half_length[a] * np.abs(ux * ca + uy * sa)
                    + bodies.half_width[a] * np.abs(-ux * sa + uy * ca))
        extent_b = (bodies.half_length[b] * np.abs(ux * cb + uy * sb)
                    + bodies.half_width[b] * np.abs(-ux * sb + uy * cb))
        separated |= np.abs(d[:, 0] * ux + d[:, 1] * uy) > extent_a + extent_b + eps
    return np.sort(np.column_stack([a, b])[~separated], axis=1)


def grid_candidates(points: np.ndarray, lo: np.ndarray, hi: np.ndarray,
                    cell: float) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Pairs ``(box, point)``: every point that lies in a grid cell the box ``[lo, hi]``
    (``(m, 2)`` corners) touches, in chunks of about ``PAIR_CHUNK`` pairs.

    Points are bucketed in square cells of side ``cell`` (made coarser if the
    points spread over more than 2**20 of them along an axis); a box covers
    a range of cells on each of its rows, which are consecutive in the points'
    sorted cell keys: one lookup per box and row, then the points in between.
    Every point inside a box is a candidate of it (more may be).
    """
    if len(points) == 0 or len(lo) == 0:
        return
    origin = points.min(axis=0)
    cell = max(cell, float(np.ptp(points, axis=0).max()) / 2**20, 1e-12)
    last = np.floor((points.max(axis=0) - origin) / cell).astype(np.int64)
    width = int(last[0]) + 1
    at = np.floor((points - origin) / cell).astype(np.int64)
    order = np.argsort(at[:, 1] * width + at[:, 0], kind="stable")
    keys = (at[:, 1] * width + at[:, 0])[order]
    with np.errstate(invalid="ignore"):
        first = np.floor((lo - origin) / cell)
        final = np.floor((hi - origin) / cell)
    inside = np.all((final >= 0) & (first <= last), axis=1)
    boxes = np.flatnonzero(inside)
    first = np.maximum(first[boxes], 0).astype(np.int64)
    final = np.minimum(final[boxes], last).astype(np.int64)
    rows = final[:, 1] - first[:, 1] + 1
    box = np.repeat(boxes, rows)
    row = np.repeat(first[:, 1], rows) + np.arange(rows.sum()) - np.repeat(np.cumsum(rows) - rows,
                                                                           rows)
    x0, x1 = np.repeat(first[:, 0], rows), np.repeat(final[:, 0], rows)
    start = np.searchsorted(keys, row * width + x0, "left")
    count = np.searchsorted(keys, row * width + x1, "right") - start
    total = np.cumsum(count)
    cuts = np.searchsorted(total, np.arange(PAIR_CHUNK, int(total[-1]) + PAIR_CHUNK, PAIR_CHUNK)
                           if len(total) else np.zeros(0, np.int64), "right")
    for lo_run, hi_run in zip([0, *cuts.tolist()], [*cuts.tolist(), len(count)], strict=True):
        part = count[lo_run:hi_run]
        if part.sum() == 0:
            continue
        offsets = np.arange(part.sum()) - np.repeat(np.cumsum(part) - part, part)
        yield (np.repeat(box[lo_run:hi_run], part),
               order[np.repeat(start[lo_run:hi_run], part) + offsets])


def validate_scenario(scenario: Scenario, where: str = "scenario",
                      labels: list[str] | None = None, allow_overlap: bool | None = None,
                      ) -> list[str]:
    """Check the start state: robots inside the bounds, clear of walls and of each other,
    goals inside the bounds.

    Every robot that starts outside the bounds, touching a wall or touching
    another robot is listed (the first few by name and position, then how
    many in all) in one line. A user who wants such a start on purpose sets
    ``allow_overlap`` (``mimics run --allow-overlap``, or ``allow_overlap =
    true`` in the scenario's settings): then the problems are returned, not
    raised. A goal outside the bounds is always an error.

    Args:
        scenario: the scenario to check.
        where: what to name in messages (a file, a scenario name).
        labels: how to name each robot (default ``robot i``).
        allow_overlap: keep such starts (default: the scenario's
            ``settings.allow_overlap``).

    Returns:
        The start problems that were allowed (empty when there were none).

    Raises:
        ScenarioError: a goal outside the bounds, or start problems when not allowed.
    """
    n = scenario.robot_count
    names = labels or [f"robot {i}" for i in range(n)]
    xmin, ymin, xmax, ymax = scenario.map.bounds
    box = f"({xmin:g}, {ymin:g}, {xmax:g}, {ymax:g})"
    gx, gy = scenario.goals[:, 0], scenario.goals[:, 1]
    with np.errstate(invalid="ignore"):
        bad_goal = np.flatnonzero(scenario.has_goal & ((gx < xmin) | (gx > xmax) | (gy < ymin)
                                                       | (gy > ymax)))
    if bad_goal.size:
        i = int(bad_goal[0])
        raise ScenarioError(f"{where}: {names[i]}: goal ({gx[i]:g}, {gy[i]:g}) is outside the "
                            f"map bounds {box}")
    problems = start_problems(scenario, names, box)
    if not problems:
        return []
    allowed = scenario.settings.allow_overlap if allow_overlap is None else allow_overlap
    if allowed:
        return problems
    shown = "; ".join(problems[:START_PROBLEMS_SHOWN])
    more = (f"; and {len(problems) - START_PROBLEMS_SHOWN} more"
            if len(problems) > START_PROBLEMS_SHOWN else "")
    raise ScenarioError(f"{where}: {shown}{more} ({len(problems)} start problem(s); keep them on "
                        "purpose with --allow-overlap or allow_overlap = true in [settings])")


START_PROBLEMS_SHOWN = 5  # named in the one-line error; the rest are counted


def start_problems(scenario: Scenario, names: list[str], box: str) -> list[str]:
    """One phrase per robot outside the bounds, robot touching a wall, pair of robots touching."""
    xmin, ymin, xmax, ymax = scenario.map.bounds
    x, y = scenario.stages[:, 0], scenario.stages[:, 1]
    problems = [f"{names[i]}: start ({x[i]:g}, {y[i]:g}) is outside the map bounds {box}"
                for i in np.flatnonzero((x < xmin) | (x > xmax) | (y < ymin) | (y > ymax))]
    bodies = Bodies.of(scenario)
    robot, segment = touching_walls(bodies, scenario.map.segments)
    seen: set[int] = set()
    for i, k in zip(robot.tolist(), segment.tolist(), strict=True):
        if i in seen:  # one wall per robot is enough to say where it is
            continue
        seen.add(i)
        x1, y1, x2, y2 = scenario.map.segments[k]
        problems.append(f"{names[i]}: robot at ({x[i]:g}, {y[i]:g}) touches wall {k} "
                        f"({x1:g}, {y1:g})-({x2:g}, {y2:g}) at the start (expected it in free "
                        "space)")
    first, second = overlapping_robots(bodies)
    for i, j in zip(first.tolist(), second.tolist(), strict=True):
        problems.append(f"{names[i]} at ({x[i]:g}, {y[i]:g}) and {names[j]} at "
                        f"({x[j]:g}, {y[j]:g}) overlap at the start (expected them apart)")
    return problems


