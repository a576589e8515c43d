"""Collisions: hand cases, and random rectangles and walls against shapely."""

import math

import numba
import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.engine.collision import Bodies, find_collisions
from mimics.engine.robot_index import build_robot_index
from mimics.engine.spatial_index import build_segment_grid
from tests import naive

BOUNDS = (-10.0, -10.0, 10.0, 10.0)


def collide(centers, headings, hl, hw, walls=(), check=None, solid=None, cell=None,
            robot_cell=1.0):
    n = len(centers)
    bodies = Bodies(np.array(centers, float).reshape(n, 2), np.array(headings, float),
                    np.array(hl, float), np.array(hw, float))
    check = np.ones(n, bool) if check is None else np.array(check)
    solid = np.ones(n, bool) if solid is None else np.array(solid)
    wall_grid = build_segment_grid(np.array(walls, float).reshape(-1, 4), BOUNDS, cell=cell)
    robots = build_robot_index(*bodies, solid, cell=robot_cell)
    with_whom, wall = find_collisions(bodies, check, solid, wall_grid, robots)
    return with_whom.tolist(), wall.tolist()


# -- hand cases ----------------------------------------------------------------------


def test_faces_in_contact_collide_and_a_micrometre_gap_does_not():
    assert collide([[0, 0], [2, 0]], [0, 0], [1, 1], [0.5, 0.5])[0] == [1, 0]
    assert collide([[0, 0], [2 + 1e-6, 0]], [0, 0], [1, 1], [0.5, 0.5])[0] == [-2, -2]


def test_corner_touching_an_edge_collides():
    # a square turned 45 degrees, its left corner on the right face of the first robot
    d = 0.5 * math.sqrt(2)
    assert collide([[0, 0], [1 + d, 0.2]], [0, math.pi / 4], [1, 0.5], [0.5, 0.5])[0] == [1, 0]
    assert collide([[0, 0], [1 + d + 1e-6, 0.2]], [0, math.pi / 4], [1, 0.5],
                   [0.5, 0.5])[0] == [-2, -2]
    # corner to corner
    assert collide([[0, 0], [2, 1]], [0, 0], [1, 1], [0.5, 0.5])[0] == [1, 0]


def test_small_robot_inside_a_big_one():
    # the small one touches none of the big one's edges, even with cells smaller than it
    for robot_cell in (1.0, 0.05, 3.0):
        got = collide([[0, 0], [1, 1]], [0.3, 1.0], [5, 0.1], [4, 0.1], robot_cell=robot_cell)
        assert got[0] == [1, 0]


def test_walls_crossing_inside_touching_or_near():
    base = dict(centers=[[0, 0]], headings=[0], hl=[1], hw=[0.5])
    assert collide(**base, walls=[[0.5, -3, 0.5, 3]]) == ([-1], [0])  # crosses
    assert collide(**base, walls=[[-0.2, 0, 0.2, 0.1]]) == ([-1], [0])  # inside
    assert collide(**base, walls=[[1, 0.5, 3, 2]]) == ([-1], [0])  # touches a corner
    assert collide(**base, walls=[[1, 3, 1, -3]]) == ([-1], [0])  # along the front face
    assert collide(**base, walls=[[1 + 1e-6, -3, 1 + 1e-6, 3]]) == ([-2], [-1])
    assert collide(**base, walls=[[1.2, 0.5, 2, -0.5]]) == ([-2], [-1])


def test_rotated_robot_against_a_wall():
    # heading 30 degrees: the front-left corner sits at (cos30 - 0.5 sin30, sin30 + 0.5 cos30)
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    corner_y = s + 0.5 * c
    base = dict(centers=[[0, 0]], headings=[math.pi / 6], hl=[1], hw=[0.5])
    assert collide(**base, walls=[[-3, corner_y, 3, corner_y]]) == ([-1], [0])
    assert collide(**base, walls=[[-3, corner_y + 1e-6, 3, corner_y + 1e-6]]) == ([-2], [-1])


def test_lowest_indices_and_robot_before_wall():
    centers = [[0, 0], [5, 0], [1.5, 0], [-1.5, 0]]  # robots 2 and 3 touch robot 0
    walls = [[8, 8, 9, 9], [0, -0.5, 0, 0.5], [-0.5, 0, 0.5, 0], [9, 9, 9, 8]]
    with_whom, wall = collide(centers, [0] * 4, [1, 0.5, 0.5, 0.5], [0.5] * 4, walls=walls)
    assert with_whom[0] == 2 and wall[0] == 1  # a robot is reported before a wall
    with_whom, wall = collide(centers, [0] * 4, [1, 0.5, 0.5, 0.5], [0.5] * 4, walls=walls,
                              solid=[True, True, False, False])
    assert with_whom[0] == -1 and wall[0] == 1
    assert with_whom[2] == 0 and with_whom[3] == 0  # non-solid robots still hit solid ones


def test_unchecked_robots_report_nothing():
    got = collide([[0, 0], [1, 0]], [0, 0], [1, 1], [0.5, 0.5], walls=[[0, -1, 0, 1]],
                  check=[False, True])
    assert got == ([-2, 0], [-1, 0])


def test_robots_outside_the_map_and_no_robots():
    got = collide([[50, 50], [51, 50]], [0, 0], [1, 1], [0.5, 0.5], walls=[[0, -1, 0, 1]])
    assert got == ([1, 0], [-1, -1])
    empty = Bodies(np.zeros((0, 2)), np.zeros(0), np.zeros(0), np.zeros(0))
    with_whom, wall = find_collisions(empty, np.zeros(0, bool), np.zeros(0, bool),
                                      build_segment_grid(np.zeros((0, 4)), BOUNDS))
    assert with_whom.shape == wall.shape == (0,)


def test_robot_grid_is_built_when_not_given():
    bodies = Bodies(np.array([[0.0, 0.0], [1.0, 1.0]]), np.zeros(2), np.array([5.0, 0.1]),
                    np.array([4.0, 0.1]))
    walls = build_segment_grid(np.zeros((0, 4)), BOUNDS)
    with_whom, _ = find_collisions(bodies, np.ones(2, bool), np.ones(2, bool), walls)
    assert with_whom.tolist() == [1, 0]


# -- random rectangles and walls against shapely -----------------------------------------

NEAR = 1e-8  # pairs closer than this (and not overlapping deeper) may go either way


def truth(centers, headings, hl, hw, walls):
    """``(robot_pairs, robot_walls)`` as 1 (touch), 0 (apart) or -1 (too close to call)."""
    n = len(centers)
    polys = [shapely.Polygon(naive.robot_corners(*centers[i], headings[i], hl[i], hw[i]))
             for i in range(n)]
    lines = [shapely.LineString(w.reshape(2, 2)) if np.any(w[:2] != w[2:])
             else shapely.Point(w[:2]) for w in walls]

    def verdict(a, b):
        if a.buffer(-NEAR).intersects(b):
            return 1
        return 0 if a.distance(b) > NEAR else -1

    pairs = np.array([[verdict(polys[i], polys[j]) for j in range(n)] for i in range(n)])
    robot_walls = np.array([[verdict(polys[i], w) for w in lines] for i in range(n)])
    return pairs.reshape(n, n), robot_walls.reshape(n, len(walls))


def assert_consistent(with_whom, wall, check, solid, pairs, robot_walls):
    """The answer agrees with shapely wherever shapely's verdict is clear."""
    for i in range(len(check)):
        if not check[i]:
            assert with_whom[i] == -2 and wall[i] == -1
            continue
        robots = [(j, pairs[i, j]) for j in range(len(check)) if j != i and solid[j]]
        first_sure = min([j for j, v in robots if v == 1], default=None)
        if with_whom[i] >= 0:
            j = with_whom[i]
            assert solid[j] and j != i and pairs[i, j] != 0
            assert first_sure is None or j <= first_sure
        else:
            assert first_sure is None, f"robot {i} misses robot {first_sure}"
        first_wall = min(np.flatnonzero(robot_walls[i] == 1).tolist(), default=None)
        if wall[i] >= 0:
            assert robot_walls[i, wall[i]] != 0
            assert first_wall is None or wall[i] <= first_wall
        else:
            assert first_wall is None, f"robot {i} misses wall {first_wall}"
        if with_whom[i] == -1:
            assert wall[i] >= 0
        if with_whom[i] == -2:
            assert wall[i] == -1


@st.composite
def worlds(draw):
    seed = draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    n = draw(st.integers(1, 8))
    m = draw(st.integers(0, 8))
    spread = draw(st.sampled_from([2.0, 4.0, 12.0]))  # crowded to sparse
    centers = rng.uniform(-spread, spread, (n, 2))
    headings = rng.uniform(-math.pi, math.pi, n)
    if draw(st.booleans()):
        headings = np.round(headings / (math.pi / 2)) * (math.pi / 2)  # axis-aligned
    hl = rng.uniform(0.05, 2.0, n)
    hw = rng.uniform(0.05, 2.0, n)
    starts = rng.uniform(-spread, spread, (m, 2))
    walls = np.hstack([starts, starts + rng.uniform(-3, 3, (m, 2))])
    check = rng.random(n) < 0.8
    solid = rng.random(n) < 0.8
    return centers, headings, hl, hw, walls, check, solid


@settings(max_examples=150, deadline=None)
@given(world=worlds(), cell=st.sampled_from([0.2, 1.0, None]),
       robot_cell=st.sampled_from([0.1, 1.5, 20.0]))
def test_matches_shapely_and_the_naive_reference(world, cell, robot_cell):
    centers, headings, hl, hw, walls, check, solid = world
    bodies = Bodies(centers, headings, hl, hw)
    wall_grid = build_segment_grid(walls, (-5, -5, 5, 5), cell=cell)
    robots = build_robot_index(centers, headings, hl, hw, solid, cell=robot_cell)
    with_whom, wall = find_collisions(bodies, check, solid, wall_grid, robots)
    pairs, robot_walls = truth(centers, headings, hl, hw, walls)
    assert_consistent(with_whom, wall, check, solid, pairs, robot_walls)
    ref = naive.find_collisions(centers, headings, hl, hw, check, solid, walls)
    assert_consistent(*ref, check, solid, pairs, robot_walls)
    if np.all(pairs != -1) and np.all(robot_walls != -1):  # no close calls: same answer
        assert with_whom.tolist() == ref[0].tolist() and wall.tolist() == ref[1].tolist()


def test_same_answer_whatever_the_number_of_threads():
    rng = np.random.default_rng(3)
    n = 400
    bodies = Bodies(rng.uniform(0, 16, (n, 2)), rng.uniform(-4, 4, n), np.full(n, 0.16),
                    np.full(n, 0.13))
    starts = rng.uniform(0, 16, (300, 2))
    walls = build_segment_grid(np.hstack([starts, starts + rng.uniform(-1, 1, (300, 2))]),
                               (0, 0, 16, 16))
    every = np.ones(n, bool)
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = find_collisions(bodies, every, every, walls)
        numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
        many = find_collisions(bodies, every, every, walls)
    finally:
        numba.set_num_threads(before)
    assert (one[0] != -2).any() and (one[0] == -2).any()
    assert one[0].tolist() == many[0].tolist() and one[1].tolist() == many[1].tolist()


def test_bad_bodies_raise():
    walls = build_segment_grid(np.zeros((0, 4)), BOUNDS)
    bodies = Bodies(np.array([[np.nan, 0.0]]), np.zeros(1), np.ones(1), np.ones(1))
    with pytest.raises(ValueError, match="finite"):
        find_collisions(bodies, np.ones(1, bool), np.ones(1, bool), walls)
