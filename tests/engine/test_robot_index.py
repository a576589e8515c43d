"""The robot index: rectangle corners bit for bit, every visible robot in its centre's cell."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.engine.robot_index import build_robot_index
from tests.naive import robot_edges


def test_corners_by_hand():
    idx = build_robot_index(np.array([[1.0, 2.0]]), np.zeros(1), 1.0, 0.5, np.ones(1, bool))
    assert idx.corners[0].tolist() == [[2.0, 2.5], [0.0, 2.5], [0.0, 1.5], [2.0, 1.5],
                                       [2.0, 2.5]]  # front-left, rear-left, ... closed
    up = build_robot_index(np.zeros((1, 2)), np.array([math.pi / 2]), 1.0, 0.5, True)
    front = up.corners[0, [3, 0]]  # heading north: the front side is the top, 1 m up
    assert np.allclose(front[:, 1], 1.0) and np.allclose(sorted(front[:, 0]), [-0.5, 0.5])
    assert idx.radius[0] == pytest.approx(math.hypot(1.0, 0.5))


@settings(max_examples=80, deadline=None)
@given(n=st.integers(0, 40), seed=st.integers(0, 2**32 - 1),
       cell=st.sampled_from([0.05, 0.8, 30.0]))
def test_every_visible_robot_is_listed_once_in_its_cell(n, seed, cell):
    rng = np.random.default_rng(seed)
    centers = rng.uniform(-10, 10, (n, 2))
    headings = rng.uniform(-4, 4, n)
    hl, hw = rng.uniform(0.05, 1.0, n), rng.uniform(0.05, 1.0, n)
    include = rng.random(n) < 0.7
    idx = build_robot_index(centers, headings, hl, hw, include, cell=cell)
    for i in range(n):  # the same corners as the reference edges, bit for bit
        edges = [list(e) for e in robot_edges(centers[i, 0], centers[i, 1], headings[i],
                                              hl[i], hw[i])]
        assert [[*idx.corners[i, e], *idx.corners[i, e + 1]] for e in range(4)] == edges
    assert sorted(idx.grid_items.tolist()) == np.flatnonzero(include).tolist()
    nx, ny = (int(v) for v in idx.shape)
    assert nx * ny <= 4 * include.sum() + 1024 + nx + ny  # bounded cell count
    for c in range(nx * ny):
        x0 = idx.origin[0] + (c % nx) * idx.cell
        y0 = idx.origin[1] + (c // nx) * idx.cell
        for r in idx.grid_items[idx.grid_start[c]:idx.grid_start[c + 1]]:
            x, y = centers[r]
            tol = 1e-9 * idx.cell
            assert x0 - tol <= x <= x0 + idx.cell + tol and y0 - tol <= y <= y0 + idx.cell + tol
    visible = hl[include], hw[include]
    assert idx.max_radius == pytest.approx(float(np.max(np.hypot(*visible), initial=0.0)))


def test_bad_inputs_raise():
    with pytest.raises(ValueError, match="finite"):
        build_robot_index(np.array([[np.nan, 0.0]]), np.zeros(1), 1.0, 1.0, True)
    with pytest.raises(ValueError, match="cell"):
        build_robot_index(np.zeros((1, 2)), np.zeros(1), 1.0, 1.0, True, cell=0.0)
    # an invisible robot may have any pose
    idx = build_robot_index(np.array([[np.nan, 0.0]]), np.zeros(1), 1.0, 1.0, False)
    assert len(idx.grid_items) == 0
