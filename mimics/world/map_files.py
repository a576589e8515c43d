"""Map files: read any supported form into a :class:`Map`, write the plain forms.

Forms, chosen by suffix:

* ``.txt``, ``.map``, ``.segments``: one wall ``x1 y1 x2 y2`` per line (m),
  ``#`` comments, and an optional ``bounds xmin ymin xmax ymax`` line;
  without it the bounds are the walls' bounding box plus a 1 m margin;
* ``.toml``, ``.json``: ``segments = [[x1, y1, x2, y2], ...]``, optional
  ``bounds = [xmin, ymin, xmax, ymax]`` and ``name``;
* ``.svg``: a vector drawing (options ``scale``, ``tolerance``);
* ``.png``, ``.pgm``, ``.bmp``: an occupancy image (options ``resolution``,
  ``origin``, ``tolerance``, ``threshold``, ``negate``; or ``size`` and
  ``center`` for a Stage bitmap);
* ``.yaml``, ``.yml``: a ROS map_server map (option ``tolerance``);
* ``stage:cave``, ``stage:hospital``: the Stage benchmark maps, from the data folder.

>>> import tempfile, pathlib
>>> path = pathlib.Path(tempfile.mkdtemp()) / "room.txt"
>>> _ = path.write_text("bounds 0 0 4 3\\n0 0 4 0  # south wall\\n")
>>> load_map(path)
Map('room', 1 segments, bounds=(0.0, 0.0, 4.0, 3.0))
"""

from __future__ import annotations

import functools
import json
import math
import re
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from mimics.world.errors import MimicsError
from mimics.world.maps import Map, bounds_around

PLAIN_SUFFIXES = (".txt", ".map", ".segments")
IMAGE_SUFFIXES = (".png", ".pgm", ".bmp")

# name -> (Stage bitmap, world size (m), centre (m)), as in Stage's benchmark worlds
BUILTIN_MAPS: dict[str, tuple[str, tuple[float, float], tuple[float, float]]] = {
    "stage:cave": ("cave_filled.png", (16.0, 16.0), (0.0, 0.0)),
    "stage:hospital": ("hospital.png", (140.0, 60.0), (0.0, 0.5)),
}

_OPTIONS = {
    "plain": (),
    "data": (),
    "svg": ("scale", "tolerance"),
    "image": ("resolution", "origin", "tolerance", "threshold", "negate", "size", "center",
              "boundary"),
    "ros": ("tolerance",),
    "builtin": (),
}
_SPLIT = re.compile(r"[\s,]+")


def _kind(path: Path) -> str:
    suffix = path.suffix.lower()
    if suffix in PLAIN_SUFFIXES:
        return "plain"
    if suffix in (".toml", ".json"):
        return "data"
    if suffix == ".svg":
        return "svg"
    if suffix in IMAGE_SUFFIXES:
        return "image"
    if suffix in (".yaml", ".yml"):
        return "ros"
    raise MimicsError(f"{path}: unknown map file type {suffix or '(no suffix)'!r} (expected "
                      f"{', '.join(PLAIN_SUFFIXES)}, .toml, .json, .svg, "
                      f"{', '.join(IMAGE_SUFFIXES)}, .yaml or a built-in map: "
                      f"{', '.join(BUILTIN_MAPS)})")


def load_map(source: str | Path, **options: Any) -> Map:
    """Read a map from a file or a built-in name (see the module docstring for the forms).

    Args:
        source: a path, or a built-in name such as ``"stage:cave"``.
        **options: import options of the file's form (``scale``, ``resolution``...).

    Raises:
        MimicsError: unreadable or malformed file, naming the file and line, or
            an option the form does not take.
    """
    text = str(source)
    if text.startswith("stage:"):
        kind, path = "builtin", Path(text)
    else:
        path = Path(source).expanduser()
        kind = _kind(path)
    allowed = _OPTIONS[kind]
    for key in options:
        if key not in allowed:
            raise MimicsError(f"{text}: option {key!r} does not apply to this kind of map "
                              f"(expected {', '.join(allowed) or 'no options'})")
    if kind == "builtin":
        return builtin_map(text)
    if kind in ("plain", "data") and not path.is_file():
        raise MimicsError(f"{path}: map file not found")
    if kind == "plain":
        return _read_plain(path)
    if kind == "data":
        return _read_data(path)
    if kind == "svg":
        from mimics.world.map_import.svg import import_svg

        return import_svg(path, **options)
    if kind == "ros":
        from mimics.world.map_import.ros import import_ros_map

        return import_ros_map(path, **options)
    from mimics.world.map_import.raster import import_raster, stage_bitmap

    if "size" in options or "center" in options or "boundary" in options:
        bad = sorted(set(options) & {"resolution", "origin", "threshold", "negate"})
        if bad or "size" not in options:
            raise MimicsError(f"{path}: a Stage bitmap takes size, center, tolerance and "
                              f"boundary{f', not {bad[0]}' if bad else '; size is missing'}")
        return stage_bitmap(path, **options)
    return import_raster(path, **options)


@functools.cache
def builtin_map(name: str) -> Map:
    """A Stage benchmark map (``stage:cave``, ``stage:hospital``), vectorised once per process.

    Raises:
        MimicsError: an unknown name, or the Stage data is not in the data folder.
    """
    if name not in BUILTIN_MAPS:
        raise MimicsError(f"unknown built-in map {name!r} (expected one of "
                          f"{', '.join(BUILTIN_MAPS)})")
    from mimics.world.data_folder import find_stage_file
    from mimics.world.map_import.raster import stage_bitmap

    bitmap, size, center = BUILTIN_MAPS[name]
    built = stage_bitmap(find_stage_file(bitmap), size, center)
    return Map(built.segments, built.bounds, name=name.split(":", 1)[1], source=name)


def _number(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(text)
    return value


def _read_plain(path: Path) -> Map:
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise MimicsError(f"{path}: cannot read as text ({exc})") from None
    segments: list[list[float]] = []
    bounds: list[float] | None = None
    for number, raw in enumerate(lines, start=1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        words = [w for w in _SPLIT.split(line) if w]
        is_bounds = words[0].lower() == "bounds"
        if is_bounds:
            words = words[1:]
            if bounds is not None:
                raise MimicsError(f"{path}, line {number}: a second 'bounds' line (expected one)")
        try:
            values = [_number(w) for w in words]
        except ValueError:
            values = []
        if len(values) != 4:
            expected = "'bounds xmin ymin xmax ymax'" if is_bounds else "'x1 y1 x2 y2'"
            raise MimicsError(f"{path}, line {number}: expected {expected} (four numbers), got "
                              f"{line!r}")
        if is_bounds:
            bounds = values
        else:
            segments.append(values)
    return _make(path, np.array(segments, dtype=np.float64).reshape(-1, 4), bounds, path.stem,
                 "a 'bounds' line")


def _make(path: Path, segments: np.ndarray, bounds: Any, name: str, bounds_key: str) -> Map:
    if bounds is None:
        if len(segments) == 0:
            raise MimicsError(f"{path}: no walls and no bounds (expected at least one segment "
                              f"or {bounds_key})")
        bounds = bounds_around(segments)
    try:
        return Map(segments, tuple(bounds), name=name, source=str(path))
    except MimicsError as exc:
        raise MimicsError(f"{path}: {exc}") from None


def map_from_dict(data: dict[str, Any], where: str, name: str = "map") -> Map:
    """A map from ``{"segments": [[x1, y1, x2, y2], ...], "bounds": [...], "name": ...}``.

    ``where`` names the file (and table) in error messages.
    """
    known = ("segments", "bounds", "name")
    for key in data:
        if key not in known:
            raise MimicsError(f"{where}: unknown key {key!r} (expected {', '.join(known)})")
    raw = data.get("segments", [])
    if not isinstance(raw, list):
        raise MimicsError(f"{where}: segments must be a list of [x1, y1, x2, y2], got {raw!r}")
    for i, segment in enumerate(raw):
        if not _four_numbers(segment):
            raise MimicsError(f"{where}: segments[{i}] must be [x1, y1, x2, y2] numbers, got "
                              f"{segment!r}")
    bounds = data.get("bounds")
    if bounds is not None and not _four_numbers(bounds):
        raise MimicsError(f"{where}: bounds must be [xmin, ymin, xmax, ymax] numbers, got "
                          f"{bounds!r}")
    label = data.get("name", name)
    if not isinstance(label, str):
        raise MimicsError(f"{where}: name must be a string, got {label!r}")
    segments = np.array(raw, dtype=np.float64).reshape(-1, 4)
    return _make(Path(where), segments, bounds, label, "bounds")


def map_to_dict(map: Map) -> dict[str, Any]:
    """The TOML/JSON form of a map (lossless: floats are written exactly)."""
    return {"name": map.name, "bounds": list(map.bounds),
            "segments": map.segments.tolist()}


def _four_numbers(value: Any) -> bool:
    return (isinstance(value, list | tuple) and len(value) == 4
            and all(isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
                    for v in value))


def _read_data(path: Path) -> Map:
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise MimicsError(f"{path}: cannot read as text ({exc})") from None
    try:
        data = json.loads(text) if path.suffix.lower() == ".json" else tomllib.loads(text)
    except json.JSONDecodeError as exc:
        raise MimicsError(f"{path}, line {exc.lineno}: not valid JSON ({exc.msg})") from None
    except tomllib.TOMLDecodeError as exc:
        raise MimicsError(f"{path}: not valid TOML ({exc})") from None
    if not isinstance(data, dict):
        raise MimicsError(f"{path}: expected an object with segments and bounds")
    return map_from_dict(data, str(path), path.stem)


def save_map(map: Map, path: str | Path) -> Path:
    """Write ``map`` as a plain (``.txt``, ``.map``, ``.segments``), ``.toml`` or ``.json`` file.

    Floats are written in their shortest exact form, so reading the file back
    gives an equal map.
    """
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix in PLAIN_SUFFIXES:
        rows = [f"# mimics map {map.name!r}: {len(map.segments)} walls, x1 y1 x2 y2 (m)",
                "bounds " + " ".join(repr(float(b)) for b in map.bounds)]
        rows += [" ".join(repr(v) for v in row) for row in map.segments.tolist()]
        text = "\n".join(rows) + "\n"
    elif suffix == ".toml":
        text = tomli_w.dumps(map_to_dict(map))
    elif suffix == ".json":
        text = json.dumps(map_to_dict(map), indent=1) + "\n"
    else:
        raise MimicsError(f"{path}: can save a map as {', '.join(PLAIN_SUFFIXES)}, .toml or "
                          f".json, not {suffix or '(no suffix)'!r}")
    try:
        path.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise MimicsError(f"{path}: cannot write ({exc.strerror})") from None
    return path
