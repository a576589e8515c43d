"""The start check's candidates come from a grid (linear in the robots): it still finds
exactly the pairs that every-pair checks find, in the same order."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.world import start_state
from mimics.world.start_state import Bodies, grid_candidates, overlapping_robots, touching_walls


def every_robot_pair(bodies: Bodies) -> list[tuple[int, int]]:
    """Brute force: each pair through the same exact test, no candidates skipped."""
    n = len(bodies.centers)
    pairs = []
    for i in range(n):
        for j in range(i + 1, n):
            touching = start_state._touching_pairs(bodies, np.array([i]), np.array([j]),
                                                   start_state.TOUCH_EPS)
            pairs += [(i, j)] * len(touching)
    return pairs


def every_wall_pair(bodies: Bodies, segments: np.ndarray) -> list[tuple[int, int]]:
    """Brute force over every robot and wall, in the order the check gives them."""
    pairs = []
    for i in range(len(bodies.centers)):
        one = Bodies(bodies.centers[i:i + 1], bodies.headings[i:i + 1],
                     bodies.half_length[i:i + 1], bodies.half_width[i:i + 1])
        for k in range(len(segments)):
            if touching_walls(one, segments[k:k + 1])[0].size:
                pairs.append((i, k))
    return pairs


coordinate = st.floats(-3.0, 3.0, allow_nan=False)


@st.composite
def scenes(draw: st.DrawFn) -> tuple[Bodies, np.ndarray]:
    n = draw(st.integers(0, 14))
    m = draw(st.integers(0, 8))
    centers = np.array(draw(st.lists(st.tuples(coordinate, coordinate), min_size=n,
                                     max_size=n)), dtype=float).reshape(-1, 2)
    headings = np.array(draw(st.lists(st.floats(-4.0, 4.0), min_size=n, max_size=n)))
    halves = np.array(draw(st.lists(st.tuples(st.floats(0.01, 0.8), st.floats(0.01, 0.5)),
                                    min_size=n, max_size=n)), dtype=float).reshape(-1, 2)
    segments = np.array(draw(st.lists(st.tuples(coordinate, coordinate, coordinate, coordinate),
                                      min_size=m, max_size=m)), dtype=float).reshape(-1, 4)
    return Bodies(centers, headings, halves[:, 0], halves[:, 1]), segments


@settings(max_examples=150, deadline=None)
@given(scenes(), st.sampled_from([3, 1_000_000]))
def test_grid_check_finds_the_pairs_every_pair_finds(scene: tuple[Bodies, np.ndarray],
                                                     chunk: int) -> None:
    bodies, segments = scene
    start_state.PAIR_CHUNK, saved = chunk, start_state.PAIR_CHUNK  # small: many chunks
    try:
        first, second = overlapping_robots(bodies)
        robot, wall = touching_walls(bodies, segments)
    finally:
        start_state.PAIR_CHUNK = saved
    assert list(zip(first.tolist(), second.tolist(), strict=True)) == every_robot_pair(bodies)
    assert list(zip(robot.tolist(), wall.tolist(), strict=True)) == every_wall_pair(bodies,
                                                                                     segments)


def test_an_overlapping_pair_in_a_big_packed_start_is_refused() -> None:
    side = 200  # 40,000 robots 0.1 m apart, one pushed onto its neighbour
    grid = np.stack(np.meshgrid(np.arange(side) * 0.1, np.arange(side) * 0.1), -1).reshape(-1, 2)
    grid[12_345] = grid[12_346] + [0.02, 0.0]
    n = len(grid)
    bodies = Bodies(grid, np.zeros(n), np.full(n, 0.035), np.full(n, 0.035))
    first, second = overlapping_robots(bodies)
    assert list(zip(first.tolist(), second.tolist(), strict=True)) == [(12_345, 12_346)]


def test_every_point_inside_a_box_is_its_candidate() -> None:
    rng = np.random.default_rng(5)
    points = rng.uniform(-10, 10, (400, 2))
    lo = rng.uniform(-12, 10, (60, 2))
    hi = lo + rng.uniform(0, 6, (60, 2))
    found = {(int(b), int(p)) for boxes, pts in grid_candidates(points, lo, hi, 0.7)
             for b, p in zip(boxes, pts, strict=True)}
    inside = {(b, p) for b in range(60) for p in range(400)
              if np.all(points[p] >= lo[b]) and np.all(points[p] <= hi[b])}
    assert inside <= found


def test_swarm_start_keeps_clear_of_each_pillar_as_a_check_of_every_pillar_does() -> None:
    import math

    from mimics.scenarios import swarm
    from mimics.world.robot_types import EPUCK

    reach = math.hypot(EPUCK.length, EPUCK.width) / 2 + swarm.CLEARANCE + swarm.PILLAR / 2
    for robots in (1, 700, 3000):
        side = max(math.sqrt(robots * swarm.AREA_PER_ROBOT), 4.0)
        pillars = swarm._pillars(side)
        start = swarm._start(robots, side, pillars)
        assert len(start) == robots
        k = math.ceil(math.sqrt(robots * 1.3)) + 2  # the lattice _start picks from
        ticks = (np.arange(k) - (k - 1) / 2) * swarm.SPACING + side / 2
        lattice = np.stack(np.meshgrid(ticks, ticks), -1).reshape(-1, 2)
        clear = np.array([all(np.max(np.abs(q - p)) >= reach for p in pillars) for q in lattice])
        kept = {tuple(q) for q in start.tolist()}
        assert kept <= {tuple(q) for q in lattice[clear].tolist()}
        # the nearest clear points are the ones kept: none left out nearer the centre
        distance = np.hypot(*(lattice[clear] - side / 2).T)
        farthest_kept = np.hypot(*(start - side / 2).T).max()
        assert np.sum(distance < farthest_kept - 1e-9) <= robots
