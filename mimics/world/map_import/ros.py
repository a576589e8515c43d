"""ROS ``map_server`` maps: a YAML file naming an occupancy image.

Keys (as map_server): ``image`` (relative to the YAML file), ``resolution``
(m per pixel), ``origin`` ``[x, y, yaw]`` (pose of the image's bottom-left
corner), ``occupied_thresh`` (default 0.65), ``free_thresh``, ``negate``
(0/1) and ``mode``. A pixel is occupied when its occupancy
``p = (255 - value) / 255`` (``value / 255`` with ``negate``) exceeds
``occupied_thresh``; unknown and free pixels are both free space here.

>>> # map.yaml:  image: map.pgm / resolution: 0.05 / origin: [-10.0, -10.0, 0.0]
>>> # import_ros_map("map.yaml")  ->  Map with the walls of map.pgm
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from mimics.world.errors import MimicsError, read_input_text
from mimics.world.map_import.cache import cached_import
from mimics.world.map_import.raster import occupied_mask, read_gray, segments_from_occupancy
from mimics.world.maps import Map

KNOWN_KEYS = ("image", "resolution", "origin", "occupied_thresh", "free_thresh", "negate",
              "mode")


def _number(data: dict[str, Any], key: str, default: float | None, path: Path) -> float:
    value = data.get(key, default)
    if value is None:
        raise MimicsError(f"{path}: missing key {key!r} (expected a number)")
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise MimicsError(f"{path}: {key} must be a number, got {value!r}")
    return float(value)


def import_ros_map(path: str | Path, tolerance: float | None = None) -> Map:
    """A map from a map_server YAML file and the image it names.

    Args:
        path: the ``.yaml`` file.
        tolerance: Douglas-Peucker tolerance in metres (default: one pixel).

    Raises:
        MimicsError: malformed YAML, a missing or unknown key, or a missing image.
    """
    path = Path(path)
    try:
        data = yaml.safe_load(read_input_text(path, "map"))
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f", line {mark.line + 1}" if mark is not None else ""
        raise MimicsError(f"{path}{where}: not valid YAML "
                          f"({getattr(exc, 'problem', None) or exc})") from None
    if not isinstance(data, dict):
        raise MimicsError(f"{path}: expected a map_server YAML mapping (image, resolution, "
                          "origin...)")
    unknown = sorted(set(data) - set(KNOWN_KEYS))
    if unknown:
        raise MimicsError(f"{path}: unknown key {unknown[0]!r} (expected one of "
                          f"{', '.join(KNOWN_KEYS)})")
    image = data.get("image")
    if not isinstance(image, str) or not image:
        raise MimicsError(f"{path}: missing key 'image' (expected the occupancy image's file "
                          "name)")
    image_path = (path.parent / image) if not Path(image).is_absolute() else Path(image)
    if not image_path.is_file():
        raise MimicsError(f"{path}: image {image!r} not found (looked for {image_path})")
    resolution = _number(data, "resolution", None, path)
    if resolution <= 0:
        raise MimicsError(f"{path}: resolution must be positive, got {resolution}")
    origin = data.get("origin", [0.0, 0.0, 0.0])
    if (not isinstance(origin, list) or len(origin) not in (2, 3)
            or not all(isinstance(v, int | float) and not isinstance(v, bool) for v in origin)):
        raise MimicsError(f"{path}: origin must be [x, y, yaw] numbers, got {origin!r}")
    occupied_thresh = _number(data, "occupied_thresh", 0.65, path)
    negate = data.get("negate", 0)
    if negate not in (0, 1):
        raise MimicsError(f"{path}: negate must be 0 or 1, got {negate!r}")
    options = {"tolerance": tolerance, "resolution": resolution, "origin": tuple(origin),
               "occupied_thresh": occupied_thresh, "negate": negate}
    return cached_import("ros", [path, image_path], options,
                         lambda: _trace(path, image_path, resolution, tuple(origin),
                                        occupied_thresh, bool(negate), tolerance))


def _trace(path: Path, image_path: Path, resolution: float, origin: tuple[float, ...],
           occupied_thresh: float, negate: bool, tolerance: float | None) -> Map:
    """The walls of the image a map_server file names (its keys already checked)."""
    gray = read_gray(image_path)
    occupied = occupied_mask(gray, occupied_thresh, bool(negate))
    tol_px = 1.0 if tolerance is None else float(tolerance) / resolution
    segments = segments_from_occupancy(occupied, tol_px, resolution)  # origin at (0, 0) first
    height, width = occupied.shape
    corners = np.array([[0.0, 0.0], [width * resolution, 0.0],
                        [0.0, height * resolution], [width * resolution, height * resolution]])
    x0, y0 = float(origin[0]), float(origin[1])
    yaw = float(origin[2]) if len(origin) == 3 else 0.0
    if yaw:
        # map_server's yaw turns the image about its bottom-left corner
        c, s = math.cos(yaw), math.sin(yaw)
        rot = np.array([[c, -s], [s, c]])
        segments = np.hstack([segments[:, :2] @ rot.T, segments[:, 2:] @ rot.T])
        corners = corners @ rot.T
    segments = segments + np.array([x0, y0, x0, y0])
    corners = corners + np.array([x0, y0])
    bounds = (*corners.min(axis=0), *corners.max(axis=0))
    return Map(segments, bounds, name=path.stem, source=str(path))
