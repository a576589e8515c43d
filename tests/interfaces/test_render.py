"""The world renderer: geometry of the drawn robots, colours by state, in-place updates."""

import numpy as np
import pytest
from matplotlib.collections import PolyCollection

from mimics.engine.state import Status
from mimics.interfaces.render import (
    STATE_NAMES,
    WorldRenderer,
    beam_segments,
    figure_size,
    rectangle_vertices,
)

WALLS = np.array([[0.0, 0.0, 10.0, 0.0], [10.0, 0.0, 10.0, 6.0]])
BOUNDS = (0.0, 0.0, 10.0, 6.0)


def renderer(n: int = 3, **options) -> WorldRenderer:
    return WorldRenderer.create(WALLS, BOUNDS, np.full(n, 0.8), np.full(n, 0.5), **options)


def pixel(r: WorldRenderer, image: np.ndarray, xy) -> np.ndarray:
    col, row = r.world_to_pixel(np.array([xy]))[0]
    return image[int(row), int(col)].astype(int)


def test_rectangle_vertices_follow_the_heading() -> None:
    verts = rectangle_vertices(np.array([[1.0, 2.0, np.pi / 2]]), np.array([0.5]),
                               np.array([0.25]))
    # Front-left corner of a robot facing +y is ahead (y + 0.5) and to its left (x - 0.25).
    np.testing.assert_allclose(verts[0], [[0.75, 2.5], [0.75, 1.5], [1.25, 1.5], [1.25, 2.5]],
                               atol=1e-12)


def test_beam_segments_leave_out_missing_beams() -> None:
    segs = beam_segments((1.0, 1.0), 0.0, np.array([0.0, np.pi / 2, np.nan]),
                         np.array([2.0, 3.0, 1.0]))
    assert segs.shape == (2, 2, 2)
    np.testing.assert_allclose(segs[:, 1], [[3.0, 1.0], [1.0, 4.0]], atol=1e-12)


def test_figure_size_is_a_multiple_of_16_and_keeps_the_aspect() -> None:
    width, height, limits = figure_size((0, 0, 140, 60), width_px=800)
    assert width % 16 == 0 and height % 16 == 0
    assert width == 800
    assert limits[0] < 0 < 140 < limits[2]


def test_robots_are_drawn_in_the_colour_of_their_state() -> None:
    r = renderer(n=4)
    pose = np.array([[2.0, 1.5, 0.0], [5.0, 1.5, 0.3], [8.0, 1.5, 0.0], [2.0, 4.5, 1.0]])
    status = np.array([Status.ACTIVE, Status.COLLIDED, Status.REACHED_GOAL, Status.ACTIVE],
                      dtype=np.int8)
    livelock = np.array([False, True, False, True])  # a collided robot is not "in livelock"
    r.update(pose, status, 3.0, livelock=livelock)
    image = r.to_rgb()
    assert image.shape == (*figure_size(BOUNDS)[1::-1], 3)
    for xy, name in zip(pose[:, :2], ["active", "collided", "reached_goal", "livelock"],
                        strict=True):
        np.testing.assert_array_equal(pixel(r, image, xy), r.color_of(name))
    np.testing.assert_array_equal(pixel(r, image, (5.0, 4.5)), [255, 255, 255])


def test_every_state_has_a_distinct_colour() -> None:
    r = renderer()
    colours = {r.color_of(name) for name in STATE_NAMES}
    assert len(colours) == len(STATE_NAMES) == len(Status) + 1
    assert (255, 255, 255) not in colours


def test_frames_update_the_same_artists_in_place() -> None:
    r = renderer(n=2)
    before = list(r.ax.collections)
    pose = np.array([[2.0, 2.0, 0.0], [6.0, 3.0, 0.0]])
    status = np.zeros(2, dtype=np.int8)
    first = r.to_rgb().copy()
    for k in range(3):
        pose[:, 0] += 0.5
        r.update(pose, status, 0.1 * k, trails=np.zeros((2, 3, 2)),
                 beams=np.array([[[2.0, 2.0], [3.0, 2.0]]]))
        frame = r.to_rgb()
    assert list(r.ax.collections) == before
    assert not np.array_equal(first, frame)
    # The old position is background again: the static layer is restored each frame.
    np.testing.assert_array_equal(pixel(r, frame, (2.0, 2.0)), [255, 255, 255])


def test_two_thousand_robots_are_redrawn_in_place_without_new_artists() -> None:
    """What keeps big teams cheap to draw (its speed is measured in benchmarks/view_costs.py):
    every frame reuses the same few collections instead of adding an artist per robot."""
    n = 2000
    rng = np.random.default_rng(1)
    r = WorldRenderer.create(np.zeros((0, 4)), (0, 0, 140, 60), np.full(n, 0.05),
                             np.full(n, 0.05))
    pose = np.column_stack([rng.uniform(0, 140, n), rng.uniform(0, 60, n),
                            rng.uniform(-3, 3, n)])
    status = rng.integers(0, len(Status), n).astype(np.int8)
    trails = pose[:, None, :2] + np.zeros((1, 7, 2))
    r.update(pose, status, 0.0, trails=trails)
    r.to_rgb()
    artists = len(r.ax.get_children())
    moved = pose + np.array([1.0, 0.5, 0.2])
    r.update(moved, status, 1.0, trails=trails)
    image = r.to_rgb()
    assert len(r.ax.get_children()) == artists
    (bodies,) = [a for a in r.dynamic if isinstance(a, PolyCollection)]
    drawn = np.array([path.vertices[:4] for path in bodies.get_paths()])
    expected = rectangle_vertices(moved, np.full(n, 0.05), np.full(n, 0.05))
    np.testing.assert_allclose(drawn, expected[:, :4], atol=1e-12)
    for name in {STATE_NAMES[s] for s in status}:  # every state present is painted
        assert np.any(np.all(image == r.color_of(name), axis=-1))


@pytest.mark.parametrize("name", ["active", "error"])
def test_colours_can_be_overridden(name: str) -> None:
    r = renderer(colors={name: "#000000"})
    assert r.color_of(name) == (0, 0, 0)
