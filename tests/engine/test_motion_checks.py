"""The step's checks in one call give what the separate functions give, bit for bit:
collisions, goal distances and the goals-and-bounds screen."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.engine.collision import Bodies, collide
from mimics.engine.motion_checks import check_moved
from mimics.engine.robot_index import index_robots
from mimics.engine.spatial_index import build_segment_grid
from tests.threads import thread_count

BOUNDS = (-4.0, -3.0, 5.0, 4.0)


def _bits(values: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(values).view(np.int64)


@settings(max_examples=200, deadline=None, derandomize=True)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 12), walls=st.integers(0, 6),
       tolerance=st.sampled_from([0.0, 0.2, 1.5]))
def test_one_call_equals_index_collide_distance_and_screen(seed: int, n: int, walls: int,
                                                           tolerance: float) -> None:
    _check_against_the_separate_functions(seed, n, walls, tolerance)


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize(("n", "spread"), [(100, 1.0), (200, 2.0), (3000, 20.0)])
def test_teams_checked_on_helper_threads_give_the_same_bits(seed: int, n: int,
                                                            spread: float) -> None:
    """From 64 checked robots the checks run in chunks of 24 on the helper threads too
    (called again and again: a helper that slept joins the calls after the first)."""
    with thread_count(2):
        for _ in range(5):
            _check_against_the_separate_functions(seed, n, 40, 0.2, spread=spread)


def _check_against_the_separate_functions(seed: int, n: int, walls: int, tolerance: float,
                                          spread: float = 1.0) -> None:
    rng = np.random.default_rng(seed)
    # robots crowded into a box a little larger than the bounds: some touch, some leave
    pose = np.column_stack([rng.uniform(-5, 6, n) * spread, rng.uniform(-4, 5, n) * spread,
                            rng.uniform(-np.pi, np.pi, n)])
    half_length, half_width = rng.uniform(0.05, 0.8, n), rng.uniform(0.05, 0.5, n)
    radius = np.hypot(half_length, half_width)
    solid = rng.random(n) < 0.8
    ids = np.flatnonzero(rng.random(n) < 0.7).astype(np.int64)
    goal = pose[:, :2] + rng.normal(0.0, 1.0, (n, 2))
    goal[rng.random(n) < 0.2] = np.nan  # robots without a goal
    segments = rng.uniform(-5, 6, (walls, 4))
    wall_grid = build_segment_grid(segments, BOUNDS)
    cell = float(rng.choice([0.3, 1.0, 4.0]))

    centers, headings = np.ascontiguousarray(pose[:, :2]), np.ascontiguousarray(pose[:, 2])
    index = index_robots(centers, headings, half_length, half_width, solid, cell, radius)
    checks = check_moved(index, pose, half_length, half_width, ids, wall_grid, goal, BOUNDS,
                         tolerance)

    check = np.zeros(n, dtype=bool)
    check[ids] = True
    with_whom, _ = collide(Bodies(centers, headings, half_length, half_width), check, wall_grid,
                           index)
    assert checks.with_whom.tolist() == with_whom.tolist()
    assert checks.touching == int(np.count_nonzero(with_whom != -2))
    distance = np.hypot(goal[:, 0] - pose[:, 0], goal[:, 1] - pose[:, 1])
    assert np.array_equal(_bits(checks.distance), _bits(distance))
    x, y = pose[ids, 0], pose[ids, 1]
    outside = (x < BOUNDS[0]) | (x > BOUNDS[2]) | (y < BOUNDS[1]) | (y > BOUNDS[3])
    assert checks.quiet == (not (outside.any() or (distance[ids] <= tolerance).any()))


def test_a_robot_on_the_boundary_or_at_the_tolerance_is_not_quiet() -> None:
    none = np.zeros(0, dtype=np.int64)
    walls = build_segment_grid(np.zeros((0, 4)), BOUNDS)
    sizes = np.full(2, 0.1)
    radius = np.hypot(sizes, sizes)
    solid = np.ones(2, dtype=bool)

    def quiet(pose: list[list[float]], goal: list[list[float]], ids: np.ndarray) -> bool:
        poses = np.array(pose)
        index = index_robots(np.ascontiguousarray(poses[:, :2]), np.ascontiguousarray(poses[:, 2]),
                             sizes, sizes, solid, 1.0, radius)
        return check_moved(index, poses, sizes, sizes, ids, walls, np.array(goal), BOUNDS,
                           0.5).quiet

    far = [[0.0, 0.0], [3.0, 3.0]]
    everyone = np.arange(2, dtype=np.int64)
    assert quiet([[1.0, 1.0, 0.0], [2.0, 2.0, 0.0]], far, everyone)
    assert quiet([[5.0, 1.0, 0.0], [2.0, 2.0, 0.0]], far, everyone)  # on the edge: inside
    assert not quiet([[5.001, 1.0, 0.0], [2.0, 2.0, 0.0]], far, everyone)
    assert not quiet([[1.0, 1.0, 0.0], [2.5, 3.0, 0.0]], far, everyone)  # 0.5 from its goal
    assert quiet([[1.0, 1.0, 0.0], [2.5, 3.0, 0.0]], far, np.array([0]))  # not checked
    assert quiet([[1.0, 1.0, 0.0], [2.0, 2.0, 0.0]], far, none)
