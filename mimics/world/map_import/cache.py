"""What a map's import produced, kept on disk so the next run reads it instead of redoing it.

Vectorising a bitmap (``raster.py``) costs scikit-image's import and the
tracing itself, about a second for Stage's cave, for the same segments every
time. So the segments and bounds an import gives are stored in the user cache
folder (``platformdirs.user_cache_dir("mimics")/maps``, or
``$MIMICS_CACHE_DIR/maps``), under a key made of:

- the SHA-256 of every source file the import reads (a changed file is a new key);
- :data:`IMPORTER_VERSION` (raise it when an importer's output changes);
- the importer's name and its options, and the sources' paths (the map's name and
  source are taken from them).

An entry carries the digest of its own arrays: one that cannot be read, or
whose digest does not match (a write cut short, a disk error), is rebuilt and
written again, never trusted. Entries are written to a temporary file and
renamed, so a reader sees a whole entry or none. A cache folder that cannot be
written (read-only home) only costs the next run the import again.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from mimics.world.maps import Map

CACHE_ENV = "MIMICS_CACHE_DIR"
# Raise when any importer's segments for the same file and options would change.
IMPORTER_VERSION = 1


def maps_folder() -> Path:
    """Where imported maps are kept: ``$MIMICS_CACHE_DIR/maps`` or the user cache folder."""
    chosen = os.environ.get(CACHE_ENV)
    if chosen:
        return Path(chosen).expanduser() / "maps"
    import platformdirs

    return Path(platformdirs.user_cache_dir("mimics", appauthor=False)) / "maps"


def entry_key(importer: str, sources: Sequence[Path], options: dict[str, object]) -> str:
    """The cache key of an import: its sources' contents, the importers' version, its options."""
    digest = hashlib.sha256(f"{importer}\0{IMPORTER_VERSION}\0{sorted(options.items())!r}".encode())
    for source in sources:  # the path too: the map's name and source are taken from it
        digest.update(f"{Path(source).resolve()}\0".encode())
        digest.update(hashlib.sha256(Path(source).read_bytes()).digest())
    return digest.hexdigest()


def _check(segments: np.ndarray, bounds: np.ndarray, name: str, source: str) -> np.ndarray:
    digest = hashlib.sha256(segments.tobytes() + bounds.tobytes()
                            + f"{name}\0{source}".encode()).digest()
    return np.frombuffer(digest, dtype=np.uint8)


def _read(path: Path) -> Map | None:
    """The entry's map, or None when it is missing or not whole."""
    try:
        with np.load(path, allow_pickle=False) as entry:
            segments, bounds, check = entry["segments"], entry["bounds"], entry["check"]
            name, source = str(entry["name"]), str(entry["source"])
    except Exception:  # missing, truncated or not an archive at all: rebuild
        return None
    if (segments.dtype != np.float64 or segments.ndim != 2 or segments.shape[1] != 4
            or bounds.dtype != np.float64 or bounds.shape != (4,)
            or not np.array_equal(check, _check(segments, bounds, name, source))):
        return None
    return Map(segments, tuple(float(b) for b in bounds), name=name, source=source)


def _write(path: Path, made: Map) -> None:
    segments = np.ascontiguousarray(made.segments, dtype=np.float64)
    bounds = np.asarray(made.bounds, dtype=np.float64)
    with contextlib.suppress(OSError):
        path.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
        try:
            with os.fdopen(handle, "wb") as out:
                np.savez(out, segments=segments, bounds=bounds, name=np.str_(made.name),
                         source=np.str_(made.source),
                         check=_check(segments, bounds, made.name, made.source))
            os.replace(temporary, path)
        finally:
            with contextlib.suppress(OSError):
                os.unlink(temporary)


def cached_import(importer: str, sources: Sequence[Path], options: dict[str, object],
                  build: Callable[[], Map]) -> Map:
    """The map ``build()`` gives, from the cache when an entry for the same inputs is whole.

    Args:
        importer: the importer's name (part of the key).
        sources: every file the import reads; each must exist (``build`` reports a
            missing one, so a source that cannot be read is left to it).
        options: the import's options (part of the key; their ``repr`` must be stable).
        build: the import itself.
    """
    try:
        key = entry_key(importer, sources, options)
    except OSError:  # a source cannot be read: the importer says why
        return build()
    path = maps_folder() / f"{key}.npz"
    found = _read(path)
    if found is not None:
        return found
    made = build()
    _write(path, made)
    return made
