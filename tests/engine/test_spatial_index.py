"""The segment grid lists each segment in exactly the cells it crosses (vs shapely)."""

import math

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from mimics.engine.spatial_index import (
    MAX_CELLS,
    build_segment_grid,
    choose_cell_size,
    grid_pad,
)

coords = st.floats(-7.0, 7.0, allow_nan=False, allow_infinity=False)


def cell_boxes(grid):
    """Shapely boxes of every cell, in cell-id order."""
    nx, ny = (int(v) for v in grid.shape)
    ix, iy = np.meshgrid(np.arange(nx), np.arange(ny))
    x0 = grid.origin[0] + ix.ravel() * grid.cell
    y0 = grid.origin[1] + iy.ravel() * grid.cell
    return shapely.box(x0, y0, x0 + grid.cell, y0 + grid.cell)


def segment_geometry(seg):
    x1, y1, x2, y2 = (float(v) for v in seg)
    if math.hypot(x2 - x1, y2 - y1) < 1e-100:
        # shapely's distance divides by the squared length, which underflows
        return shapely.Point(x1, y1)
    return shapely.LineString([(x1, y1), (x2, y2)])


def listed_cells(grid):
    """``{segment: set of cell ids}`` read back from the CSR arrays."""
    out = {s: set() for s in range(len(grid.segments))}
    for c in range(len(grid.cell_start) - 1):
        for p in range(grid.cell_start[c], grid.cell_start[c + 1]):
            out[int(grid.cell_items[p])].add(c)
    return out


def assert_exact_listing(grid):
    """Every crossed cell lists the segment; no cell farther than the pad does."""
    start, items = grid.cell_start, grid.cell_items
    assert start[0] == 0 and start[-1] == len(items)
    assert np.all(np.diff(start) >= 0)
    assert len(start) == int(grid.shape[0]) * int(grid.shape[1]) + 1
    for c in range(len(start) - 1):
        in_cell = items[start[c]:start[c + 1]]
        assert len(set(in_cell.tolist())) == len(in_cell), "a segment listed twice in a cell"
    boxes = cell_boxes(grid)
    pad = grid_pad(grid.origin, grid.shape, grid.cell)
    listed = listed_cells(grid)
    for s, seg in enumerate(grid.segments):
        geom = segment_geometry(seg)
        crossed = set(np.flatnonzero(shapely.intersects(boxes, geom)).tolist())
        assert crossed <= listed[s], f"segment {s} missing from cells {crossed - listed[s]}"
        distance = shapely.distance(boxes[sorted(listed[s])], geom)
        assert np.all(distance <= 2 * pad + 1e-12), f"segment {s} listed in a far cell"


def test_diagonal_wall_fills_only_the_cells_along_it():
    grid = build_segment_grid(np.array([[0.2, 0.5, 9.8, 9.6]]), (0, 0, 10, 10), cell=1.0)
    assert grid.shape.tolist() == [10, 10]
    assert len(grid.cell_items) == 19  # the bounding box would be 100 cells
    assert_exact_listing(grid)


def test_segments_on_cell_sides_and_corners_are_listed_on_both_sides():
    frame = build_segment_grid(np.zeros((0, 4)), (0, 0, 3, 3), cell=1.0)
    xs = frame.origin[0] + np.arange(4) * frame.cell  # the grid's own lines
    ys = frame.origin[1] + np.arange(4) * frame.cell
    segs = np.array([[0.5, ys[1], 2.5, ys[1]],  # along a row boundary
                     [xs[2], 0.5, xs[2], 2.5],  # along a column boundary
                     [xs[1], ys[1], xs[2], ys[2]],  # from cell corner to cell corner
                     [xs[1], ys[1], xs[1], ys[1]]])  # a point on a corner
    grid = build_segment_grid(segs, (0, 0, 3, 3), cell=1.0)
    assert grid.origin.tolist() == frame.origin.tolist() and grid.cell == frame.cell
    assert_exact_listing(grid)
    listed = listed_cells(grid)
    assert listed[0] == {0, 1, 2, 3, 4, 5}  # both rows, all three columns
    assert listed[1] == {1, 2, 4, 5, 7, 8}
    assert listed[2] == {0, 1, 3, 4, 5, 7, 8}
    assert listed[3] == {0, 1, 3, 4}  # the corner point is in its four cells


def test_grid_covers_segments_outside_the_bounds():
    segs = np.array([[-30.0, 2.0, -25.0, 2.0], [4.0, 40.0, 5.0, 41.0]])
    grid = build_segment_grid(segs, (0, 0, 10, 10))
    top = grid.origin + grid.shape * grid.cell
    assert grid.origin[0] <= -30 and grid.origin[1] <= 0
    assert top[0] >= 10 and top[1] >= 41
    assert_exact_listing(grid)


def test_empty_map_is_one_cell():
    grid = build_segment_grid(np.zeros((0, 4)), (0, 0, 16, 16))
    assert grid.shape.tolist() == [1, 1]
    assert grid.cell_start.tolist() == [0, 0]


def test_owner_defaults_to_walls_and_is_checked():
    segs = np.array([[0, 0, 1, 1], [1, 1, 2, 0]], dtype=float)
    assert build_segment_grid(segs, None).owner.tolist() == [-1, -1]
    assert build_segment_grid(segs, None, owner=[3, 4]).owner.tolist() == [3, 4]
    with pytest.raises(ValueError, match="owner"):
        build_segment_grid(segs, None, owner=[3])


def test_bad_inputs_raise():
    with pytest.raises(ValueError, match="finite"):
        build_segment_grid(np.array([[0, 0, np.nan, 1]]), (0, 0, 1, 1))
    with pytest.raises(ValueError, match="cell"):
        build_segment_grid(np.array([[0, 0, 1, 1]]), (0, 0, 1, 1), cell=0.0)
    with pytest.raises(ValueError, match="cells"):
        build_segment_grid(np.array([[0, 0, 1, 1]]), (0, 0, 1e4, 1e4), cell=1e-3)


def test_choose_cell_size_bounds_the_number_of_cells():
    rng = np.random.default_rng(1)
    starts = rng.uniform(0, 100, (5000, 2))
    tiny = np.hstack([starts, starts + 0.001])  # many 1 mm segments
    cell = choose_cell_size(tiny, (0, 0, 100, 100))
    assert (100 / cell) ** 2 <= 4 * 5000 + 1024 + 1e-6
    long = np.array([[0, 0, 16, 0], [0, 16, 16, 16], [0, 0, 0, 16], [16, 0, 16, 16]], float)
    assert choose_cell_size(long, (0, 0, 16, 16)) == 16.0  # a room is one cell
    assert choose_cell_size(np.zeros((0, 4)), (0, 0, 3, 2)) == 3.0
    assert MAX_CELLS > 1e6


@settings(max_examples=150, deadline=None)
@given(segs=arrays(np.float64, st.tuples(st.integers(1, 40), st.just(4)), elements=coords))
def test_choose_cell_size_is_twice_the_median_length_when_no_limit_applies(segs):
    lengths = np.hypot(segs[:, 2] - segs[:, 0], segs[:, 3] - segs[:, 1])
    box = (-7.0, -7.0, 7.0, 7.0)
    expected = 2.0 * float(np.median(lengths))  # NumPy's median: the rule's own words
    limits = (math.sqrt(14.0 * 14.0 / (4 * len(segs) + 1024)), 14.0 / 4096)
    if expected > max(limits) and expected < 14.0:  # neither floor nor ceiling applies
        assert choose_cell_size(segs, box) == expected


@settings(max_examples=150, deadline=None)
@given(segs=arrays(np.float64, st.tuples(st.integers(0, 6), st.just(4)), elements=coords),
       cell=st.sampled_from([0.37, 1.0, 2.5, None]))
def test_every_segment_is_in_every_cell_it_crosses(segs, cell):
    assert_exact_listing(build_segment_grid(segs, (-5, -5, 5, 5), cell=cell))


# -- robot edges ----------------------------------------------------------------------
