"""Sight lists from a fixed point: hand-drawn cases, and no beam at any heading changes."""

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from mimics.engine.ranging.point_cull import SightLists, sight_lists
from mimics.engine.ranging.ranger import RangerQuery, beam_fans, offset_units, trace_beams
from mimics.engine.ranging.wall_index import build_wall_index
from mimics.engine.robot_index import build_robot_index

NO_ROBOTS = (np.zeros(0, np.int64), np.zeros((0, 2)), np.zeros(0), np.zeros(0))


def seen_walls(walls, origin=(0.0, 0.0), limit=8.0):
    segments = np.array(walls, dtype=float)
    kept, _ = sight_lists(*origin, limit, -1, np.arange(len(segments)), segments, *NO_ROBOTS)
    return kept.tolist()


def test_a_wall_behind_a_wall_is_dropped_and_one_seen_past_its_end_is_kept():
    walls = [[2.0, -3.0, 2.0, 3.0], [4.0, -1.0, 4.0, 1.0], [4.0, 2.0, 4.0, 6.0]]
    assert seen_walls(walls) == [0, 2]
    assert seen_walls(walls, limit=1.9) == []  # all beyond the range


def test_a_long_oblique_wall_hides_by_its_near_pieces():
    # the long wall's far ends are 10 m away, but where it covers the short wall it is
    # about 1 m away: only its pieces can hide the short wall 3 m away
    assert seen_walls([[1.0, -10.0, 1.0, 10.0], [3.0, -0.5, 3.0, 0.5]], limit=20.0) == [0]


def test_walls_meeting_at_a_corner_hide_nothing_seen_through_the_corner():
    # two walls meeting at (2, 0): a beam through the corner may slip between them
    # (rounding), so the wall behind the corner stays listed
    walls = [[2.0, -2.0, 2.0, 0.0], [2.0, 0.0, 2.0, 2.0], [4.0, -1.0, 4.0, 1.0]]
    assert seen_walls(walls) == [0, 1, 2]
    assert seen_walls([*walls[:2], [4.0, 0.2, 4.0, 1.0]]) == [0, 1]


def test_robots_hide_by_their_inscribed_circle_and_are_hidden_by_their_bounding_one():
    segments = np.array([[5.0, -0.2, 5.0, 0.2], [5.0, -2.0, 5.0, 2.0]])
    centers = np.array([[0.0, 0.0], [2.0, 0.0], [6.0, 0.0], [3.0, 3.0]])
    radius = np.full(4, 0.5 * math.sqrt(2.0))  # squares of half size 0.5
    inner = np.full(4, 0.5)
    walls, robots = sight_lists(0.0, 0.0, 8.0, 0, np.arange(2), segments, np.arange(4),
                                centers, radius, inner)
    # robot 1's circle (0.5 at 2 m: 14.5 degrees each way) hides the short wall only;
    # the long wall hides robot 2; robot 0 is the sensor itself
    assert walls.tolist() == [1]
    assert robots.tolist() == [1, 3]


@st.composite
def scenes(draw):
    """Walls (some long, so that some hide others), robots, and a sensor among them."""
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    m = draw(st.integers(0, 25))
    starts = rng.uniform(-6, 6, (m, 2))
    angle = rng.uniform(0, 2 * math.pi, m)
    length = rng.choice([0.05, 0.3, 2.0, 6.0], m)
    walls = np.hstack([starts, starts + length[:, None] * np.column_stack(
        [np.cos(angle), np.sin(angle)])])
    n = draw(st.integers(1, 12))
    centers = rng.uniform(-5, 5, (n, 2))
    if m and draw(st.booleans()):  # the sensor on a wall's end
        centers[0] = walls[0, :2]
    half_length, half_width = rng.uniform(0.05, 0.6, n), rng.uniform(0.05, 0.6, n)
    return walls, centers, half_length, half_width, rng


@settings(max_examples=150, deadline=None)
@given(scene=scenes(), limit=st.sampled_from([1.0, 4.0, 30.0]))
def test_no_beam_changes_whatever_the_headings(scene, limit):
    """The lists, made at one set of headings, give the very scans of the whole
    neighbourhood at any other headings of every robot (centres fixed)."""
    walls, centers, half_length, half_width, rng = scene
    n = len(centers)
    index = build_wall_index(walls, (-8, -8, 8, 8), reach=limit)
    radius = np.hypot(half_length, half_width)
    kept_walls, kept_robots = sight_lists(
        centers[0, 0], centers[0, 1], limit, 0, np.arange(len(walls)), walls,
        np.arange(n), centers, radius, np.minimum(half_length, half_width))
    spans = np.zeros((n, 4), np.int64)  # robot 0 pinned, with the lists
    spans[0] = 0, len(kept_walls), len(kept_walls), len(kept_walls) + len(kept_robots)
    sight = SightLists(np.arange(n) == 0, spans, np.concatenate([kept_walls, kept_robots]))
    offsets = np.linspace(-math.pi, math.pi, 720, endpoint=False)[None]
    for _ in range(4):
        headings = rng.uniform(-math.pi, math.pi, n)
        robots = build_robot_index(centers, headings, half_length, half_width,
                                   np.ones(n, bool), cell=1.0)
        query = RangerQuery(centers[:1].copy(), headings[:1].copy(), offsets,
                            np.array([limit]), np.zeros(1, np.int64), offset_units(offsets),
                            beam_fans(offsets))
        everything = trace_beams(query, index, robots)
        listed = trace_beams(query, index, robots, sight=sight)
        assert everything[0].tobytes() == listed[0].tobytes()
        assert everything[1].tobytes() == listed[1].tobytes()


def test_a_pinned_robot_sweeps_its_lists_alone():
    """The kernel takes a pinned robot's lists at their word (so the test above tests them)."""
    index = build_wall_index(np.array([[2.0, -1.0, 2.0, 1.0]]), (-4, -4, 4, 4), reach=8.0)
    robots = build_robot_index(np.zeros((1, 2)), np.zeros(1), 0.2, 0.2, np.ones(1, bool))
    offsets = np.zeros((1, 1))
    query = RangerQuery(np.zeros((1, 2)), np.zeros(1), offsets, np.array([8.0]),
                        np.zeros(1, np.int64), offset_units(offsets), beam_fans(offsets))
    pinned = SightLists(np.ones(1, bool), np.zeros((1, 4), np.int64), np.zeros(0, np.int64))
    assert trace_beams(query, index, robots)[0].tolist() == [[2.0]]
    assert trace_beams(query, index, robots, sight=pinned)[0].tolist() == [[8.0]]
