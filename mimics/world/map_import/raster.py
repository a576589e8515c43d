"""Occupancy images (PNG, PGM, BMP) to wall segments.

The occupied pixels are outlined with marching squares (scikit-image
``find_contours`` at the 0.5 level of a binary image padded with free
pixels, so regions touching the border are closed too) and each outline is
simplified with Douglas-Peucker (``approximate_polygon``), so that a map has
hundreds of segments rather than one per pixel edge.

Coordinates: pixel ``(row, col)`` covers ``[col, col + 1] x [row, row + 1]``
in image units; the image's y axis points down and is flipped, so the top
row is the +y side of the world.

>>> import numpy as np
>>> grid = np.zeros((10, 10), dtype=bool)
>>> grid[2:5, 3:8] = True  # a 5 x 3 px block
>>> segs = segments_from_occupancy(grid, tolerance_px=1.0)
>>> len(segs) >= 4
True
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from mimics.world.errors import MimicsError
from mimics.world.map_import.cache import cached_import
from mimics.world.maps import Map

DEFAULT_RESOLUTION = 0.05  # m per pixel, the usual ROS map resolution


def read_gray(path: str | Path) -> np.ndarray:
    """An image as greyscale in ``[0, 1]`` (1 is white); transparent pixels count as white.

    Raises:
        MimicsError: the file cannot be read as an image.
    """
    import imageio.v3 as iio

    path = Path(path)
    if not path.is_file():
        raise MimicsError(f"{path}: image file not found")
    try:
        image = np.asarray(iio.imread(path, plugin="pillow"))  # PNG, PGM and BMP alike
    except Exception as exc:  # imageio raises many types for a bad file
        raise MimicsError(f"{path}: not a readable image ({type(exc).__name__}: {exc})") from None
    if image.dtype == bool:
        return image.astype(np.float64)
    if not np.issubdtype(image.dtype, np.number) or image.ndim not in (2, 3):
        raise MimicsError(f"{path}: expected a greyscale or colour image, got an array of shape "
                          f"{image.shape} and type {image.dtype}")
    top = float(np.iinfo(image.dtype).max) if np.issubdtype(image.dtype, np.integer) else 1.0
    values = image.astype(np.float64) / top
    if values.ndim == 2:
        return values
    channels = values.shape[2]
    if channels in (2, 4):  # grey or colour with alpha: blend over white
        alpha = values[..., -1]
        values = values[..., :-1]
    else:
        alpha = np.ones(values.shape[:2])
    if values.shape[2] >= 3:
        gray = values[..., :3] @ np.array([0.2125, 0.7154, 0.0721])  # skimage's rgb2gray weights
    else:
        gray = values[..., 0]
    return gray * alpha + (1.0 - alpha)


def occupied_mask(gray: np.ndarray, threshold: float = 0.5, negate: bool = False) -> np.ndarray:
    """Occupied pixels: darkness ``1 - gray`` (or ``gray`` when ``negate``) above ``threshold``.

    With 8-bit images and the default threshold this is Stage's rule: a value
    of 127 or less is an obstacle.
    """
    darkness = gray if negate else 1.0 - gray
    return darkness > threshold


def outlines(occupied: np.ndarray, tolerance_px: float = 1.0) -> list[np.ndarray]:
    """Simplified outlines of the occupied regions, as closed ``(k, 2)`` arrays of (row, col).

    Points are in pixel-edge coordinates: ``(0, 0)`` is the image's top-left corner.
    """
    from skimage.measure import approximate_polygon, find_contours  # 0.9 s: only when tracing

    padded = np.pad(np.asarray(occupied, dtype=np.float64), 1)
    rings = []
    for contour in find_contours(padded, 0.5):
        # find_contours works on pixel centres of the padded image; shift to edge coordinates
        ring = approximate_polygon(contour, tolerance_px) - 0.5
        if len(ring) >= 3:
            rings.append(ring)
    return rings


def segments_from_rings(rings: list[np.ndarray],
                        to_world: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """Consecutive vertices of each ring as segments ``(m, 4)``, zero-length ones dropped."""
    parts = []
    for ring in rings:
        points = to_world(ring)
        parts.append(np.hstack([points[:-1], points[1:]]))
    if not parts:
        return np.zeros((0, 4))
    segments = np.vstack(parts)
    keep = (segments[:, 0] != segments[:, 2]) | (segments[:, 1] != segments[:, 3])
    return segments[keep]


def segments_from_occupancy(occupied: np.ndarray, tolerance_px: float = 1.0,
                            resolution: float = 1.0,
                            origin: tuple[float, float] = (0.0, 0.0)) -> np.ndarray:
    """Wall segments (m) around the occupied pixels of a boolean grid (row 0 at the top).

    The bottom-left corner of the grid is at ``origin``; a pixel is
    ``resolution`` metres wide.
    """
    height = occupied.shape[0]

    def to_world(ring: np.ndarray) -> np.ndarray:
        return np.column_stack([origin[0] + ring[:, 1] * resolution,
                                origin[1] + (height - ring[:, 0]) * resolution])

    return segments_from_rings(outlines(occupied, tolerance_px), to_world)


def _positive(value: float, name: str, path: Path) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not value > 0:
        raise MimicsError(f"{path}: {name} must be a positive number, got {value!r}")
    return float(value)


def _tolerance_px(tolerance: float | None, metres_per_px: float, path: Path) -> float:
    if tolerance is None:
        return 1.0
    if isinstance(tolerance, bool) or not isinstance(tolerance, int | float) or tolerance < 0:
        raise MimicsError(f"{path}: tolerance must be a number of metres >= 0, got {tolerance!r}")
    return float(tolerance) / metres_per_px


def import_raster(path: str | Path, resolution: float = DEFAULT_RESOLUTION,
                  origin: tuple[float, float] = (0.0, 0.0), tolerance: float | None = None,
                  threshold: float = 0.5, negate: bool = False) -> Map:
    """A map from an occupancy image: dark pixels are walls.

    Args:
        path: a PNG, PGM or BMP file.
        resolution: metres per pixel.
        origin: world position of the image's bottom-left corner (m).
        tolerance: Douglas-Peucker tolerance in metres (default: one pixel).
        threshold: darkness above which a pixel is occupied (0 white, 1 black).
        negate: white means occupied.

    Returns:
        A map whose bounds are the image's extent (from the map cache, ``cache.py``,
        when this image was imported with these options before).
    """
    path = Path(path)
    options = {"resolution": resolution, "origin": tuple(origin), "tolerance": tolerance,
               "threshold": threshold, "negate": negate}
    return cached_import("raster", [path], options,
                         lambda: _import_raster(path, resolution, origin, tolerance, threshold,
                                                negate))


def _import_raster(path: Path, resolution: float, origin: tuple[float, float],
                   tolerance: float | None, threshold: float, negate: bool) -> Map:
    resolution = _positive(resolution, "resolution", path)
    occupied = occupied_mask(read_gray(path), threshold, negate)
    segments = segments_from_occupancy(occupied, _tolerance_px(tolerance, resolution, path),
                                       resolution, (float(origin[0]), float(origin[1])))
    height, width = occupied.shape
    bounds = (origin[0], origin[1], origin[0] + width * resolution,
              origin[1] + height * resolution)
    return Map(segments, bounds, name=path.stem, source=str(path))


def stage_bitmap(path: str | Path, size: tuple[float, float],
                 center: tuple[float, float] = (0.0, 0.0), tolerance: float | None = None,
                 boundary: bool = True) -> Map:
    """A map from a Stage floorplan bitmap, following Stage's convention.

    A pixel is an obstacle when its 8-bit value is 127 or less. The bounding
    box of the obstacle pixels (not of the image) is scaled to ``size`` and
    centred on ``center``; the image's top row is the world's +y side. With
    ``boundary`` four walls are added along that box, as Stage's
    ``floorplan`` (``boundary 1``) does.

    Args:
        path: the bitmap.
        size: ``(width, height)`` of the world (m), Stage's ``size [x y z]``.
        center: Stage's ``pose [x y z a]`` of the floorplan (m).
        tolerance: Douglas-Peucker tolerance in metres (default: one pixel).
        boundary: add the four boundary walls.

    Raises:
        MimicsError: unreadable image, a bad size, or no obstacle pixels.

    Taken from the map cache (``cache.py``) when this bitmap was imported with
    these options before.
    """
    path = Path(path)
    options = {"size": tuple(size), "center": tuple(center), "tolerance": tolerance,
               "boundary": boundary}
    return cached_import("stage_bitmap", [path], options,
                         lambda: _stage_bitmap(path, size, center, tolerance, boundary))


def _stage_bitmap(path: Path, size: tuple[float, float], center: tuple[float, float],
                  tolerance: float | None, boundary: bool) -> Map:
    width, height = (_positive(v, "size", path) for v in size)
    occupied = occupied_mask(read_gray(path))
    rows = np.flatnonzero(occupied.any(axis=1))
    cols = np.flatnonzero(occupied.any(axis=0))
    if rows.size == 0:
        raise MimicsError(f"{path}: no obstacle pixels (value <= 127), so Stage's scaling is "
                          "undefined")
    r0, r1, c0, c1 = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
    kx, ky = width / (c1 - c0), height / (r1 - r0)
    left, top = center[0] - width / 2, center[1] + height / 2

    def to_world(ring: np.ndarray) -> np.ndarray:
        return np.column_stack([left + (ring[:, 1] - c0) * kx, top - (ring[:, 0] - r0) * ky])

    tol_px = _tolerance_px(tolerance, (kx + ky) / 2, path)
    segments = segments_from_rings(outlines(occupied, tol_px), to_world)
    xmin, ymin, xmax, ymax = left, top - height, left + width, top
    if boundary:
        box = np.array([[xmin, ymin, xmax, ymin], [xmax, ymin, xmax, ymax],
                        [xmax, ymax, xmin, ymax], [xmin, ymax, xmin, ymin]])
        segments = np.vstack([segments, box])
    return Map(segments, (xmin, ymin, xmax, ymax), name=path.stem, source=str(path))
