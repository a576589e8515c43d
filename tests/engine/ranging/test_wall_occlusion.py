"""Walls hidden from a cell: hand-drawn cases, and no beam from the cell loses its hit."""

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.engine.ranging.wall_index import build_wall_index
from mimics.engine.ranging.wall_occlusion import MARGIN, hidden_by_one
from tests import naive

CELL = (0.0, 0.0, 1.0, 1.0)


def test_a_wall_behind_a_long_wall_is_hidden_and_one_beside_it_is_not():
    walls = np.array([[2.0, -3.0, 2.0, 4.0],  # the occluder, x = 2 from y = -3 to 4
                      [4.0, -1.0, 4.0, 2.0],  # behind it
                      [4.0, 3.0, 4.0, 9.0]])  # past y = 7 seen over its end from (1, 1)
    assert hidden_by_one(walls, 0, 1, CELL)
    assert not hidden_by_one(walls, 0, 2, CELL)
    assert not hidden_by_one(walls, 1, 0, CELL)  # a wall never hides a nearer one


def test_walls_touching_the_occluder_or_its_line_are_kept():
    walls = np.array([[2.0, -3.0, 2.0, 4.0],
                      [2.0, 0.5, 4.0, 0.5],  # a T: starts on the occluder
                      [2.0 + MARGIN / 2, -1.0, 5.0, -1.0],  # starts within the margin
                      [2.0 + 2 * MARGIN, -1.0, 5.0, -2.0]])  # just clear of it: hidden
    assert not hidden_by_one(walls, 0, 1, CELL)
    assert not hidden_by_one(walls, 0, 2, CELL)
    assert hidden_by_one(walls, 0, 3, CELL)


def test_an_occluder_whose_line_crosses_the_cell_hides_nothing():
    walls = np.array([[0.5, 2.0, 0.5, 9.0],  # its line x = 0.5 runs through the cell
                      [-1.0, 5.0, 2.0, 5.0]])
    assert not hidden_by_one(walls, 0, 1, CELL)


def test_a_wall_seen_past_the_occluders_end_from_one_corner_only_is_kept():
    # over the occluder's end (2, 1.8), the corner (0, 1) sees x = 6 above y = 3.4; the
    # other corners see only higher up
    occluder = [2.0, -3.0, 2.0, 1.8]
    assert not hidden_by_one(np.array([occluder, [6.0, 0.0, 6.0, 3.6]]), 0, 1, CELL)
    assert hidden_by_one(np.array([occluder, [6.0, 0.0, 6.0, 3.2]]), 0, 1, CELL)


@st.composite
def maps(draw):
    """Long walls (so that some hide others) and a few short ones."""
    m = draw(st.integers(2, 14))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    starts = rng.uniform(-6, 6, (m, 2))
    angle = rng.uniform(0, 2 * math.pi, m)
    length = rng.choice([0.3, 2.0, 6.0], m)
    ends = starts + length[:, None] * np.column_stack([np.cos(angle), np.sin(angle)])
    return np.hstack([starts, ends]), rng


@settings(max_examples=120, deadline=None)
@given(scene=maps(), near_cell=st.sampled_from([0.5, 1.0, 2.5]))
def test_no_beam_from_a_cell_loses_its_nearest_wall(scene, near_cell):
    """From points of each cell (its corners among them), in many directions, the nearest
    hit among the cell's list is the nearest among all walls (the naive reference)."""
    walls, rng = scene
    reach = 9.0
    index = build_wall_index(walls, (-6, -6, 6, 6), reach=reach, near_cell=near_cell)
    near = index.near
    nx = int(near.shape[0])
    for c in range(len(near.cell_start) - 1):
        listed = near.cell_items[near.cell_start[c]:near.cell_start[c + 1]]
        x0 = near.origin[0] + (c % nx) * near.cell
        y0 = near.origin[1] + (c // nx) * near.cell
        side = near.cell
        eyes = [(x0, y0), (x0 + side, y0 + side),
                *zip(rng.uniform(x0, x0 + side, 3), rng.uniform(y0, y0 + side, 3), strict=True)]
        for eye in eyes:
            # the beams toward every wall end, and some at random
            targets = np.concatenate([walls[:, :2], walls[:, 2:]])
            angles = np.concatenate([np.arctan2(targets[:, 1] - eye[1], targets[:, 0] - eye[0]),
                                     rng.uniform(-math.pi, math.pi, 8)])
            for angle in angles:
                d = (math.cos(angle), math.sin(angle))
                hits = [naive.ray_hit(eye, d, w) for w in walls]
                best = min(hits)
                if best <= reach:
                    assert min(hits[s] for s in listed) == best
