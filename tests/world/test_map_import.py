"""Importers: SVG drawings, occupancy images, Stage bitmaps and ROS maps."""

from pathlib import Path

import imageio.v3 as iio
import numpy as np
import pytest
import shapely

from mimics.world.errors import MimicsError
from mimics.world.map_files import load_map
from mimics.world.map_import import import_raster, import_ros_map, import_svg, stage_bitmap
from tests.stage import stage_file

SVG_HEAD = '<svg xmlns="http://www.w3.org/2000/svg" '


def write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def unordered(segments: np.ndarray) -> set[tuple[float, ...]]:
    """Segments as a set, each with its ends in a fixed order, rounded."""
    out = set()
    for x1, y1, x2, y2 in np.round(segments, 9).tolist():
        a, b = sorted([(x1 + 0.0, y1 + 0.0), (x2 + 0.0, y2 + 0.0)])
        out.add((*a, *b))
    return out


# -- SVG ---------------------------------------------------------------------

def test_svg_lines_rect_and_transforms_match_hand_computed_walls(tmp_path: Path) -> None:
    path = write(tmp_path / "room.svg", SVG_HEAD + 'width="20" height="10" viewBox="0 0 20 10">'
                 '<line x1="1" y1="2" x2="5" y2="2"/>'
                 '<rect x="10" y="1" width="4" height="2" transform="translate(1, 3)"/>'
                 '<g transform="translate(2,0) scale(2)"><polyline points="0,4 1,4 1,5"/></g>'
                 '<text x="3" y="3">ignored</text></svg>')
    room = import_svg(path, scale=0.5)  # 0.5 m per SVG unit, y flipped about the height (10)
    expected = np.array([
        [0.5, 4.0, 2.5, 4.0],  # the line
        [5.5, 3.0, 7.5, 3.0], [7.5, 3.0, 7.5, 2.0], [7.5, 2.0, 5.5, 2.0], [5.5, 2.0, 5.5, 3.0],
        [1.0, 1.0, 2.0, 1.0], [2.0, 1.0, 2.0, 0.0],  # polyline (2,8) (4,8) (4,10) in px
    ])
    assert unordered(room.segments) == unordered(expected)
    assert room.bounds == (0.0, 0.0, 10.0, 5.0)
    assert room.name == "room"


def test_svg_physical_units_without_scale(tmp_path: Path) -> None:
    path = write(tmp_path / "mm.svg", SVG_HEAD + 'width="100mm" height="50mm" '
                 'viewBox="0 0 100 50"><line x1="10" y1="5" x2="30" y2="5"/></svg>')
    drawing = load_map(path)
    assert np.allclose(drawing.segments, [[0.01, 0.045, 0.03, 0.045]], atol=1e-12)
    assert np.allclose(drawing.bounds, (0.0, 0.0, 0.1, 0.05))


def test_svg_curves_are_flattened_within_tolerance(tmp_path: Path) -> None:
    path = write(tmp_path / "pillar.svg", SVG_HEAD + 'width="10" height="10" '
                 'viewBox="0 0 10 10"><circle cx="5" cy="4" r="2"/>'
                 '<path d="M 0 9 Q 5 5 10 9"/></svg>')
    pillar = import_svg(path, scale=1.0, tolerance=0.01)
    centre = np.array([5.0, 6.0])  # y flipped: 10 - 4
    ends = pillar.segments.reshape(-1, 2, 2)
    on_circle = np.abs(np.hypot(*(ends - centre).transpose(2, 0, 1)) - 2.0) < 1e-9
    circle = ends[on_circle.all(axis=1)]
    assert len(circle) >= 20
    middles = circle.mean(axis=1)
    sag = 2.0 - np.hypot(*(middles - centre).T)
    assert sag.max() <= 0.0101
    assert len(pillar.segments) > len(circle)  # the quadratic curve is there too


@pytest.mark.parametrize(("text", "expected"), [
    ("<svg this is not xml", "not a valid SVG"),
    (SVG_HEAD + 'width="10" height="10"><text x="1" y="1">only text</text></svg>',
     "no lines or shapes"),
    (SVG_HEAD + 'width="10" height="10"></svg>', "no lines or shapes"),
])
def test_svg_errors_name_the_file(tmp_path: Path, text: str, expected: str) -> None:
    path = write(tmp_path / "bad.svg", text)
    with pytest.raises(MimicsError, match=expected) as info:
        load_map(path)
    assert str(path) in str(info.value)
    with pytest.raises(MimicsError, match="scale must be a positive number"):
        import_svg(path, scale=-1.0)


# -- occupancy images ----------------------------------------------------------

def box_distance(points: np.ndarray, box: tuple[float, float, float, float]) -> np.ndarray:
    """Distance of each point to the boundary of an axis-aligned box."""
    x0, y0, x1, y1 = box
    x, y = points[:, 0], points[:, 1]
    outside = np.hypot(np.maximum(np.maximum(x0 - x, x - x1), 0),
                       np.maximum(np.maximum(y0 - y, y - y1), 0))
    inside = np.minimum.reduce([x - x0, x1 - x, y - y0, y1 - y])
    return np.where(outside > 0, outside, np.abs(inside))


def test_raster_rectangles_round_trip_within_one_pixel(tmp_path: Path) -> None:
    height, width, res, origin = 60, 80, 0.1, (-1.0, 2.0)
    blocks = [(5, 14, 10, 29), (30, 49, 50, 69), (0, 9, 70, 79)]  # rows, cols inclusive
    image = np.full((height, width), 255, dtype=np.uint8)
    for r0, r1, c0, c1 in blocks:
        image[r0:r1 + 1, c0:c1 + 1] = 0
    path = tmp_path / "blocks.png"
    iio.imwrite(path, image)
    grid = import_raster(path, resolution=res, origin=origin, tolerance=0.5 * res)
    assert grid.bounds == pytest.approx((-1.0, 2.0, -1.0 + width * res, 2.0 + height * res))
    boxes = [(origin[0] + c0 * res, origin[1] + (height - r1 - 1) * res,
              origin[0] + (c1 + 1) * res, origin[1] + (height - r0) * res)
             for r0, r1, c0, c1 in blocks]
    ends = grid.segments.reshape(-1, 2)
    nearest = np.min([box_distance(ends, box) for box in boxes], axis=0)
    assert nearest.max() < res  # every vertex lies within one pixel of a block's outline
    for box in boxes:
        own = ends[box_distance(ends, box) < res]
        assert np.allclose(own.min(axis=0), box[:2], atol=res)
        assert np.allclose(own.max(axis=0), box[2:], atol=res)
    assert len(grid.segments) < 60  # simplified: a few per block, not one per pixel


def test_stage_bitmap_scales_the_obstacle_box_and_flips_y(tmp_path: Path) -> None:
    image = np.full((12, 20), 255, dtype=np.uint8)
    image[1, 2:18] = image[10, 2:18] = 0  # a frame: the obstacle box is rows 1-10, cols 2-17
    image[1:11, 2] = image[1:11, 17] = 0
    image[4:6, 5:8] = 0  # a block near the top
    path = tmp_path / "floor.png"
    iio.imwrite(path, image)
    floor = stage_bitmap(path, size=(8.0, 5.0), center=(1.0, 0.5))  # 0.5 m per pixel
    assert floor.bounds == (-3.0, -2.0, 5.0, 3.0)
    box = {(-3.0, -2.0, 5.0, -2.0), (-3.0, -2.0, -3.0, 3.0), (-3.0, 3.0, 5.0, 3.0),
           (5.0, -2.0, 5.0, 3.0)}
    assert box <= unordered(floor.segments)  # Stage's boundary walls
    ends = floor.segments.reshape(-1, 2)
    block = ends[(ends[:, 0] > -2.0) & (ends[:, 0] < 0.5) & (ends[:, 1] > 0.0)
                 & (ends[:, 1] < 2.0)]
    assert np.allclose(block.min(axis=0), (-1.5, 0.5), atol=0.5)
    assert np.allclose(block.max(axis=0), (0.0, 1.5), atol=0.5)
    without = stage_bitmap(path, size=(8.0, 5.0), center=(1.0, 0.5), boundary=False)
    assert len(without.segments) == len(floor.segments) - 4
    blank = tmp_path / "blank.png"
    iio.imwrite(blank, np.full((5, 5), 255, dtype=np.uint8))
    with pytest.raises(MimicsError, match="no obstacle pixels"):
        stage_bitmap(blank, size=(1.0, 1.0))


def obstacle_area(segments: np.ndarray) -> float:
    """Area enclosed by the walls under the even-odd rule (outlines of obstacle regions)."""
    faces = shapely.get_parts(shapely.polygonize(shapely.linestrings(segments.reshape(-1, 2, 2))))
    area = 0.0
    x1, y1, x2, y2 = segments.T
    for face in faces:
        point = face.representative_point()
        px, py = point.x, point.y
        crossing = (y1 > py) != (y2 > py)
        with np.errstate(divide="ignore", invalid="ignore"):
            x_at = x1 + (py - y1) * (x2 - x1) / (y2 - y1)
        if np.count_nonzero(crossing & (x_at > px)) % 2 == 1:
            area += face.area
    return area


def test_cave_free_area_matches_the_bitmap() -> None:
    path = stage_file("cave_filled.png")
    cave = stage_bitmap(path, size=(16.0, 16.0), boundary=False)
    image = iio.imread(path)
    rows = np.flatnonzero((image <= 127).any(axis=1))
    cols = np.flatnonzero((image <= 127).any(axis=0))
    box = image[rows[0]:rows[-1] + 1, cols[0]:cols[-1] + 1]
    free_fraction_bitmap = np.count_nonzero(box > 127) / box.size
    free_fraction_map = 1.0 - obstacle_area(cave.segments) / (16.0 * 16.0)
    assert free_fraction_map == pytest.approx(free_fraction_bitmap, rel=0.02)
    assert 0.70 < free_fraction_map < 0.82  # the README's 76%
    assert 50 < len(cave.segments) < 1000  # hundreds of segments, not one per pixel


def test_builtin_stage_maps() -> None:
    stage_file("cave_filled.png")
    cave = load_map("stage:cave")
    assert cave.bounds == (-8.0, -8.0, 8.0, 8.0)
    assert cave.source == "stage:cave"
    hospital = load_map("stage:hospital")
    assert hospital.bounds == pytest.approx((-70.0, -29.5, 70.0, 30.5))
    assert load_map("stage:cave") is cave  # vectorised once per process


def test_not_an_image_names_the_file(tmp_path: Path) -> None:
    path = write(tmp_path / "photo.png", "hello, not a PNG")
    with pytest.raises(MimicsError, match="not a readable image") as info:
        load_map(path)
    assert str(path) in str(info.value)
    with pytest.raises(MimicsError, match="image file not found"):
        import_raster(tmp_path / "missing.pgm")


# -- ROS map_server --------------------------------------------------------------

def write_ros_map(folder: Path, extra: str = "", image_name: str = "map.pgm",
                  negate: object = 0) -> Path:
    image = np.full((20, 30), 254, dtype=np.uint8)
    image[5:10, 10:15] = 0
    image[15:18, 2:4] = 205  # unknown (occupancy 0.2): free space here
    iio.imwrite(folder / "map.pgm", image)
    return write(folder / "map.yaml", f"image: {image_name}\nresolution: 0.05\n"
                 "origin: [-1.0, -2.0, 0.0]\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
                 f"negate: {negate}\n{extra}")


def test_ros_map_places_the_image_at_its_origin(tmp_path: Path) -> None:
    ros = load_map(write_ros_map(tmp_path))
    assert ros.bounds == pytest.approx((-1.0, -2.0, 0.5, -1.0))
    ends = ros.segments.reshape(-1, 2)
    assert np.allclose(ends.min(axis=0), (-0.5, -1.5), atol=0.05)
    assert np.allclose(ends.max(axis=0), (-0.25, -1.25), atol=0.05)
    negated = import_ros_map(write_ros_map(tmp_path, negate=1))  # now white is occupied
    assert np.allclose(negated.segments.reshape(-1, 2).min(axis=0), (-1.0, -2.0), atol=0.05)


@pytest.mark.parametrize(("extra", "image", "negate", "expected"), [
    ("", "nowhere.pgm", 0, "image 'nowhere.pgm' not found"),
    ("mood: happy\n", "map.pgm", 0, "unknown key 'mood'"),
    ("", "map.pgm", 2, "negate must be 0 or 1"),
])
def test_ros_map_errors_name_the_yaml_file(tmp_path: Path, extra: str, image: str,
                                           negate: int, expected: str) -> None:
    path = write_ros_map(tmp_path, extra, image, negate)
    with pytest.raises(MimicsError, match=expected) as info:
        import_ros_map(path)
    assert str(path) in str(info.value)
    broken = write(tmp_path / "broken.yaml", "image: [unclosed\n")
    with pytest.raises(MimicsError, match=r"broken\.yaml, line \d+: not valid YAML"):
        import_ros_map(broken)


# -- the map cache -------------------------------------------------------------

@pytest.fixture
def traced(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """A fresh map cache folder, and a list that grows by one at each actual tracing."""
    from mimics.world.map_import import raster

    monkeypatch.setenv("MIMICS_CACHE_DIR", str(tmp_path / "cache"))
    calls: list[int] = []
    outlines = raster.outlines

    def counted(*args: object, **kwargs: object) -> list[np.ndarray]:
        calls.append(1)
        return outlines(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(raster, "outlines", counted)
    return calls


def blocks_image(path: Path, width: int) -> Path:
    image = np.full((20, 30), 255, np.uint8)
    image[4:9, 3:3 + width] = 0
    iio.imwrite(path, image)
    return path


def test_map_cache_gives_the_traced_map_without_tracing_again(tmp_path: Path,
                                                              traced: list[int]) -> None:
    path = blocks_image(tmp_path / "room.png", 6)
    first = stage_bitmap(path, (3.0, 2.0))
    again = stage_bitmap(path, (3.0, 2.0))
    assert len(traced) == 1  # the second came from the cache
    assert again.segments.tobytes() == first.segments.tobytes()
    assert (again.bounds, again.name, again.source) == (first.bounds, first.name, first.source)
    other_size = stage_bitmap(path, (6.0, 2.0))  # other options: another entry
    assert len(traced) == 2
    assert other_size.segments[:, 0].max() == pytest.approx(2 * first.segments[:, 0].max())
    raster_map = import_raster(path, resolution=0.1)
    import_raster(path, resolution=0.1)
    assert len(traced) == 3
    assert raster_map.bounds == (0.0, 0.0, 3.0, 2.0)


def test_map_cache_is_invalidated_by_a_changed_file_or_importer_version(
        tmp_path: Path, traced: list[int], monkeypatch: pytest.MonkeyPatch) -> None:
    from mimics.world.map_import import cache

    path = blocks_image(tmp_path / "room.png", 6)
    narrow = import_raster(path)
    blocks_image(path, 10)  # same name, other walls
    wide = import_raster(path)
    assert len(traced) == 2
    assert np.ptp(wide.segments[:, 0]) > np.ptp(narrow.segments[:, 0])
    monkeypatch.setattr(cache, "IMPORTER_VERSION", cache.IMPORTER_VERSION + 1)
    assert import_raster(path).segments.tobytes() == wide.segments.tobytes()
    assert len(traced) == 3


@pytest.mark.parametrize("damage", ["truncate", "garbage", "flip a byte of the segments"])
def test_map_cache_rebuilds_a_damaged_entry(tmp_path: Path, traced: list[int],
                                            damage: str) -> None:
    path = blocks_image(tmp_path / "room.png", 6)
    first = import_raster(path)
    (entry,) = (tmp_path / "cache" / "maps").glob("*.npz")
    data = entry.read_bytes()
    if damage == "truncate":
        entry.write_bytes(data[: len(data) // 2])
    elif damage == "garbage":
        entry.write_bytes(b"not an archive")
    else:  # a valid archive whose segments no longer match their digest
        from mimics.world.map_import import cache

        with np.load(entry) as old:
            arrays = {key: old[key] for key in old.files}
        arrays["segments"] = arrays["segments"] + 1.0
        with entry.open("wb") as out:
            np.savez(out, **arrays)
        assert cache._read(entry) is None
    rebuilt = import_raster(path)
    assert len(traced) == 2
    assert rebuilt.segments.tobytes() == first.segments.tobytes()
    import_raster(path)  # the rebuilt entry was written again, whole
    assert len(traced) == 2
