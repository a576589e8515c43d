"""Download the Stage benchmark maps and worlds (GPL-2.0 data, never shipped with mimics).

The files come from the Stage repository (rtv/Stage) on GitHub and are checked
against SHA-256 checksums of the copies the built-in Cave and Hospital
scenarios were made with, so a changed or corrupted file is refused rather
than silently giving a different map.

>>> sorted(STAGE_FILES)[:2]
['STAGE-LICENSE.txt', 'cave.world']
"""

from __future__ import annotations

import hashlib
import os
import tempfile
import urllib.error
import urllib.request
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from mimics.world.errors import MimicsError

STAGE_BASE_URL = "https://raw.githubusercontent.com/rtv/Stage/master"

Progress = Callable[[str, int, int | None], None]
"""Called as ``progress(file_name, bytes_received, total_bytes_or_None)``."""


@dataclass(frozen=True)
class DataFile:
    """One file to download: its path in the repository and its SHA-256."""

    remote: str
    sha256: str


STAGE_FILES: dict[str, DataFile] = {
    "cave_filled.png": DataFile(
        "worlds/bitmaps/cave_filled.png",
        "d2ee4830160e7a171d9d70d3f5a8aac9345f50e798ce32d61c12eadea2792350"),
    "hospital.png": DataFile(
        "worlds/bitmaps/hospital.png",
        "6c7d4a88bebc9a887aeec719ea68475c836e983a5d3d9e290074522847c52cca"),
    "cave.world": DataFile(
        "worlds/benchmark/cave.world",
        "68ef6027880a40032876f4fb824c6a1032a70a22f83a3ac87ac12bfba026346c"),
    "hospital.world": DataFile(
        "worlds/benchmark/hospital.world",
        "0ba8e39873b1f10f20e18d6241b901e23f82f0fab271a37ccd602060f2950214"),
    "STAGE-LICENSE.txt": DataFile(
        "COPYING.txt",
        "32b1062f7da84967e7019d01ab805935caa7ab7321a7ced0e30ebe75e5df1670"),
}

_CHUNK = 64 * 1024


def _sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with path.open("rb") as handle:
        for block in iter(lambda: handle.read(_CHUNK), b""):
            digest.update(block)
    return digest.hexdigest()


def _fetch(url: str, name: str, timeout: float, progress: Progress | None) -> bytes:
    """The body at ``url``; one-line MimicsError when it cannot be had."""
    try:
        with urllib.request.urlopen(url, timeout=timeout) as response:
            length = response.headers.get("Content-Length")
            total = int(length) if length and length.isdigit() else None
            chunks: list[bytes] = []
            received = 0
            while block := response.read(_CHUNK):
                chunks.append(block)
                received += len(block)
                if progress is not None:
                    progress(name, received, total)
    except urllib.error.HTTPError as exc:
        raise MimicsError(f"cannot download {url}: HTTP {exc.code} {exc.reason}") from None
    except (urllib.error.URLError, OSError) as exc:
        reason = getattr(exc, "reason", exc)
        raise MimicsError(f"cannot download {url}: {reason} (are you offline? or pass another "
                          "--url)") from None
    return b"".join(chunks)


def _write_atomically(path: Path, data: bytes) -> None:
    """Write via a temporary file in the same folder, so a reader never sees half a file."""
    handle, temp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".part")
    try:
        with os.fdopen(handle, "wb") as out:
            out.write(data)
        os.replace(temp, path)
    except BaseException:
        Path(temp).unlink(missing_ok=True)
        raise


def download_stage(dest: str | Path, base_url: str = STAGE_BASE_URL,
                   progress: Progress | None = None, timeout: float = 30.0) -> list[Path]:
    """Download the Stage files into ``dest`` (normally ``<data folder>/stage``).

    Files already present with the right checksum are kept. Each file is
    checked before it replaces anything.

    Args:
        dest: the folder to write (created if needed).
        base_url: the root the files' repository paths are relative to.
        progress: optional ``progress(file_name, received, total)`` callback.
        timeout: seconds to wait for the server.

    Returns:
        The paths of all the files, downloaded or already there.

    Raises:
        MimicsError: offline, a server error, or a checksum mismatch.
    """
    folder = Path(dest).expanduser()
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise MimicsError(f"cannot create {folder}: {exc.strerror}") from None
    paths = []
    for name, spec in STAGE_FILES.items():
        path = folder / name
        paths.append(path)
        if path.is_file() and _sha256(path) == spec.sha256:
            if progress is not None:
                size = path.stat().st_size
                progress(name, size, size)
            continue
        url = f"{base_url.rstrip('/')}/{spec.remote}"
        data = _fetch(url, name, timeout, progress)
        got = hashlib.sha256(data).hexdigest()
        if got != spec.sha256:
            raise MimicsError(f"{url}: checksum mismatch (expected SHA-256 {spec.sha256[:12]}..., "
                              f"got {got[:12]}...): the file changed upstream or the download "
                              "was corrupted; it was not saved")
        try:
            _write_atomically(path, data)
        except OSError as exc:
            raise MimicsError(f"cannot write {path}: {exc.strerror}") from None
    return paths
