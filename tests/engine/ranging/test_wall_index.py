"""Near lists: the walls within reach of each cell, less hidden ones (shapely as reference)."""

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.engine.ranging import wall_index
from mimics.engine.ranging.ranger import RangerQuery, cast_rays
from mimics.engine.ranging.wall_index import (
    build_wall_index,
    near_cell_of,
    segment_box_distance,
)
from tests import naive


def near_sets(index):
    near = index.near
    return [set(near.cell_items[near.cell_start[c]:near.cell_start[c + 1]].tolist())
            for c in range(len(near.cell_start) - 1)]


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), reach=st.sampled_from([0.0, 0.5, 3.0, 40.0]),
       near_cell=st.sampled_from([None, 0.3, 2.0]))
def test_near_lists_hold_the_walls_within_reach_unless_hidden(seed, reach, near_cell):
    rng = np.random.default_rng(seed)
    starts = rng.uniform(-6, 6, (12, 2))
    walls = np.hstack([starts, starts + rng.uniform(-2, 2, (12, 2))])
    index = build_wall_index(walls, (-5, -5, 5, 5), reach=reach, near_cell=near_cell)
    near = index.near
    nx = int(near.shape[0])
    lines = [shapely.LineString(w.reshape(2, 2)) for w in walls]
    for c, listed in enumerate(near_sets(index)):
        x0 = near.origin[0] + (c % nx) * near.cell
        y0 = near.origin[1] + (c // nx) * near.cell
        box = shapely.box(x0, y0, x0 + near.cell, y0 + near.cell)
        distance = np.array([box.distance(line) for line in lines])
        for s in np.flatnonzero(distance <= index.reach - 1e-9).tolist():
            assert s in listed or hidden(box, lines[s], lines, rng)
        assert all(distance[s] <= index.reach + 1e-6 for s in listed)


def hidden(box, wall, lines, rng, samples=6):
    """Whether some other wall crosses every sight line from the box to ``wall`` (corners,
    ends and random points of both: shapely's proper crossing)."""
    x0, y0, x1, y1 = box.bounds
    eyes = [(x0, y0), (x1, y0), (x1, y1), (x0, y1),
            *zip(rng.uniform(x0, x1, samples), rng.uniform(y0, y1, samples), strict=True)]
    ends = [wall.interpolate(f, normalized=True) for f in (0.0, 1.0, *rng.uniform(0, 1, samples))]
    sights = [shapely.LineString([eye, (end.x, end.y)]) for eye in eyes for end in ends]
    return any(other is not wall and all(sight.crosses(other) for sight in sights)
               for other in lines)


@settings(max_examples=200, deadline=None)
@given(seg=st.lists(st.floats(-5, 5), min_size=4, max_size=4),
       box=st.lists(st.floats(-3, 3), min_size=2, max_size=2), side=st.floats(1e-3, 2.0))
def test_segment_box_distance_matches_shapely(seg, box, side):
    x1, y1, x2, y2 = seg
    # shapely divides by the squared length, which underflows for tiny segments
    geom = (shapely.Point(x1, y1) if np.hypot(x2 - x1, y2 - y1) < 1e-100
            else shapely.LineString([(x1, y1), (x2, y2)]))
    want = shapely.box(box[0], box[1], box[0] + side, box[1] + side).distance(geom)
    got = segment_box_distance(x1, y1, x2, y2, box[0], box[1], box[0] + side, box[1] + side)
    assert got == pytest.approx(want, abs=1e-9)


def test_points_outside_the_grid_have_no_cell():
    index = build_wall_index(np.array([[0.0, 0.0, 1.0, 0.0]]), (0, 0, 10, 10), reach=2.0)
    assert near_cell_of(index.near, -1.0, 5.0) == -1
    assert near_cell_of(index.near, 5.0, 5.0) >= 0


def test_reach_shrinks_to_fit_the_memory_budget_and_beams_still_hit(monkeypatch):
    monkeypatch.setattr(wall_index, "MAX_NEAR_ITEMS", 2000)
    rng = np.random.default_rng(1)
    starts = rng.uniform(0, 100, (400, 2))
    walls = np.hstack([starts, starts + rng.uniform(-1, 1, (400, 2))])
    index = build_wall_index(walls, (0, 0, 100, 100), reach=30.0)
    assert index.reach < 30.0 and len(index.near.cell_items) <= 4000
    origins = rng.uniform(0, 100, (20, 2))
    offsets = np.tile(np.linspace(-np.pi, np.pi, 91), (20, 1))
    query = RangerQuery(origins, np.zeros(20), offsets, np.full(20, 30.0), np.full(20, -1))
    ranges, owner = cast_rays(query, index)
    none = np.zeros(0)
    want, want_owner = naive.cast_rays(origins, np.zeros(20), offsets, np.full(20, 30.0),
                                       np.full(20, -1), walls, np.zeros((0, 2)), none, none,
                                       none, np.zeros(0, bool))
    np.testing.assert_allclose(ranges, want, rtol=0, atol=1e-9)
    np.testing.assert_array_equal(owner, want_owner)


def test_bad_reach_raises():
    with pytest.raises(ValueError, match="reach"):
        build_wall_index(np.zeros((0, 4)), (0, 0, 1, 1), reach=float("nan"))


def test_a_map_asked_for_again_shares_its_index_and_a_changed_map_does_not():
    from mimics.engine.spatial_index import build_segment_grid

    rng = np.random.default_rng(7)
    segments = rng.uniform(-5, 5, (30, 4))
    bounds = (-6.0, -6.0, 6.0, 6.0)
    grid = build_segment_grid(segments, bounds)
    first = wall_index.shared_wall_index(segments, bounds, 3.0, grid)
    assert wall_index.shared_wall_index(segments.copy(), bounds, 3.0, grid) is first
    fresh = build_wall_index(segments, bounds, 3.0, grid=grid)
    assert near_sets(first) == near_sets(fresh)  # the shared index is the plain one
    assert wall_index.shared_wall_index(segments, bounds, 2.0, grid) is not first
    moved = segments.copy()
    moved[3, 0] += 1e-9  # one coordinate, one ulp-scale move: another map
    moved_grid = build_segment_grid(moved, bounds)
    other = wall_index.shared_wall_index(moved, bounds, 3.0, moved_grid)
    assert other is not first
    assert near_sets(other) == near_sets(build_wall_index(moved, bounds, 3.0, grid=moved_grid))
    for reach in (4.0, 5.0, 6.0, 7.0):  # more maps than are kept: the first is gone
        wall_index.shared_wall_index(segments, bounds, reach, grid)
    assert wall_index.shared_wall_index(segments, bounds, 3.0, grid) is not first
