"""The Maps page's API: list, open, save and import map files of the workspace.

Maps are read with :func:`mimics.world.map_files.load_map` (so every form the
CLI reads opens here, the importers included) and saved with
:func:`~mimics.world.map_files.save_map`, as the plain files ``mimics run`` reads.
"""

from __future__ import annotations

import json
import tempfile
from pathlib import Path, PurePosixPath
from typing import Any

from fastapi import APIRouter, Depends, HTTPException, Request
from pydantic import Field

from mimics.interfaces.web.bodies import StrictBody, no_fields
from mimics.interfaces.web.wording import upload_for_page
from mimics.world.errors import MimicsError
from mimics.world.limits import check_map_extent
from mimics.world.map_files import (
    BUILTIN_MAPS,
    IMAGE_SUFFIXES,
    PLAIN_SUFFIXES,
    load_map,
    map_from_dict,
    map_to_dict,
    save_map,
)
from mimics.world.maps import Map

router = APIRouter(prefix="/api/maps", tags=["maps"])

MAP_SUFFIXES = (*PLAIN_SUFFIXES, ".toml", ".json", ".svg", *IMAGE_SUFFIXES, ".yaml", ".yml")
SAVE_SUFFIXES = (*PLAIN_SUFFIXES, ".toml", ".json")
IMPORT_SUFFIXES = (".svg", *IMAGE_SUFFIXES, ".yaml", ".yml", *SAVE_SUFFIXES)
IMPORT_OPTIONS = ("scale", "tolerance", "resolution", "origin", "threshold", "negate", "size",
                  "center")


class MapBody(StrictBody):
    """A map to save: ``path`` under ``maps/`` ending in .txt, .map, .segments, .toml or .json."""

    path: str
    name: str = "map"
    bounds: list[float] = Field(min_length=4, max_length=4)
    segments: list[list[float]] = Field(default_factory=list, max_length=200_000)
    # False: an existing file is kept and the answer is 409 (the page asks, then sends True)
    overwrite: bool = True


def refuse_overwrite(real: Path, path: str, overwrite: bool) -> None:
    """409 when ``real`` exists and the request did not say to replace it."""
    if not overwrite and real.exists():
        raise HTTPException(409, f"{path} exists already: replace it?")


def check_extent(bounds: Any, segments: Any, name: str = "map") -> None:
    """422 for a map too large for the simulator (``mimics.world.limits.check_map_extent``):
    found here, not when a run fails on it far from the page."""
    try:
        check_map_extent(name, bounds, segments)
    except MimicsError as exc:
        raise HTTPException(422, str(exc)) from None


def map_json(the_map: Map, path: str) -> dict[str, Any]:
    """The JSON the page draws: path, name, bounds, segments and their count."""
    return {"path": path, **map_to_dict(the_map), "walls": len(the_map.segments)}


def builtin_available(name: str) -> bool:
    """True when the Stage data of a built-in map is on this machine."""
    from mimics.world.data_folder import find_stage_file

    try:
        find_stage_file(BUILTIN_MAPS[name][0])
    except Exception:
        return False
    return True


def open_map(request: Request, path: str) -> Map:
    """Load a workspace map file or a built-in map (``stage:cave``) for the API."""
    if path in BUILTIN_MAPS:
        return load_map(path)
    real = request.app.state.workspace.resolve(path, must_exist=True)
    if real.suffix.lower() not in MAP_SUFFIXES or not real.is_file():
        raise HTTPException(400, f"{path}: not a map file (expected one of "
                                 f"{', '.join(MAP_SUFFIXES)})")
    return load_map(real)


def _options(text: str) -> dict[str, Any]:
    """Import options from their JSON text, checked against :data:`IMPORT_OPTIONS`."""
    try:
        parsed = json.loads(text)
    except ValueError:
        raise HTTPException(400, "options: expected a JSON object") from None
    if not isinstance(parsed, dict) or any(k not in IMPORT_OPTIONS for k in parsed):
        raise HTTPException(400, f"options: expected a JSON object with keys among "
                                 f"{', '.join(IMPORT_OPTIONS)}")
    for key in ("origin", "size", "center"):
        if isinstance(parsed.get(key), list):
            parsed[key] = tuple(parsed[key])
    return parsed


@router.get("")
def list_maps(request: Request) -> dict[str, Any]:
    """The workspace's map files and the built-in maps available here."""
    workspace = request.app.state.workspace
    files = sorted(p for p in workspace.folder("maps").rglob("*")
                   if p.is_file() and p.suffix.lower() in MAP_SUFFIXES)
    return {"files": [{"path": workspace.relative(p), "name": p.stem,
                       "bytes": p.stat().st_size} for p in files],
            "builtin": [name for name in BUILTIN_MAPS if builtin_available(name)]}


@router.get("/file")
def get_map(request: Request, path: str) -> dict[str, Any]:
    """A map's name, bounds and wall segments (any form ``load_map`` reads)."""
    return map_json(open_map(request, path), path)


@router.put("/file")
def put_map(request: Request, body: MapBody) -> dict[str, Any]:
    """Save a map drawn in the page as the file the CLI runs."""
    workspace = request.app.state.workspace
    real = workspace.resolve(body.path)
    if workspace.folder("maps") not in real.parents:
        raise HTTPException(400, f"{body.path}: maps are saved under maps/")
    if real.suffix.lower() not in SAVE_SUFFIXES:
        raise HTTPException(400, f"{body.path}: save a map as {', '.join(SAVE_SUFFIXES)}")
    the_map = map_from_dict({"name": body.name, "bounds": body.bounds,
                             "segments": body.segments}, body.path, body.name)
    check_extent(the_map.bounds, the_map.segments.tolist())
    refuse_overwrite(real, body.path, body.overwrite)
    real.parent.mkdir(parents=True, exist_ok=True)
    save_map(the_map, real)
    return map_json(load_map(real), workspace.relative(real))


@router.post("/import")
async def import_map(request: Request, filename: str, options: str = "{}") -> dict[str, Any]:
    """Turn an uploaded drawing, image or ROS map into walls with the existing importers.

    The body is the file's bytes; ``filename`` gives its form (suffix);
    ``options`` is a JSON object of import options (``resolution``, ``scale``...).
    Nothing is saved: the page shows the walls and their count, then saves them.
    """
    suffix = PurePosixPath(filename).suffix.lower()
    if suffix not in IMPORT_SUFFIXES or "/" in filename or "\\" in filename:
        raise HTTPException(400, f"filename {filename!r}: expected a file name ending in "
                                 f"{', '.join(IMPORT_SUFFIXES)}")
    if suffix in (".yaml", ".yml"):
        raise HTTPException(400, "a ROS map YAML names its image: put both in the workspace "
                                 "and import with /api/maps/import-file")
    parsed = _options(options)
    data = await request.body()
    if not data:
        raise HTTPException(400, "the upload is empty")
    with tempfile.TemporaryDirectory(prefix="mimics-import-") as folder:
        path = Path(folder) / PurePosixPath(filename).name
        path.write_bytes(data)
        try:
            the_map = load_map(path, **parsed)
        except MimicsError as exc:  # named as uploaded, not by the server's temporary path
            raise HTTPException(422, upload_for_page(str(exc), folder, path.name)) from None
    check_extent(the_map.bounds, the_map.segments.tolist(), "options: the imported map")
    return map_json(the_map, "")


@router.post("/import-file", dependencies=[Depends(no_fields)])
def import_file(request: Request, path: str, options: str = "{}") -> dict[str, Any]:
    """Import a drawing, image or ROS YAML already in the workspace (preview, nothing saved)."""
    real = request.app.state.workspace.resolve(path, must_exist=True)
    if real.suffix.lower() not in IMPORT_SUFFIXES or not real.is_file():
        raise HTTPException(400, f"{path}: expected a file ending in "
                                 f"{', '.join(IMPORT_SUFFIXES)}")
    parsed = _options(options)
    the_map = load_map(real, **parsed)
    check_extent(the_map.bounds, the_map.segments.tolist(), "options: the imported map")
    return map_json(the_map, "")
