"""Which parts of the first-run compile Numba's disk cache lacks, told without importing Numba.

``mimics run`` starts the compile processes of a fresh install before it
imports NumPy, Numba and the engine (about 0.5 s on one core), so that the
second core compiles meanwhile (:mod:`mimics.interfaces.cli.compiling.first_run`). This
module answers ``mimics.engine.compiling.warm_up.missing_parts`` without that import:
it looks for each witness kernel's index file (``.nbi``) where Numba would
put it, mirroring the cache locators of ``numba.core.caching`` that apply to
an installed or editable mimics, in Numba's order:

1. ``NUMBA_CACHE_DIR`` when set: a folder named after the module's folder and
   the SHA-1 of its path (``UserProvidedCacheLocator``);
2. ``__pycache__`` beside the module when it can be made and written to
   (``InTreeCacheLocator``);
3. else the user's cache folder, ``$XDG_CACHE_HOME/numba`` or
   ``~/.cache/numba`` on Linux, named as in 1 (``UserWideCacheLocator``).

Like Numba, a folder counts only if it can be made and a file written in it.
The index file is ``module.qualname-LINE.pyXY.nbi``; any line is accepted, as
``warm_up.missing_parts`` does. Where it cannot be sure (locators chosen by
``NUMBA_CACHE_LOCATOR_CLASSES``, a ``.numba_config.yaml``, another system than
Linux, a frozen program) it answers ``None`` and the caller asks Numba.
A test checks the answer against Numba's own for every witness.
"""

from __future__ import annotations

import hashlib
import os
import re
import sys
import tempfile
from pathlib import Path

# A kernel of each part whose index file in Numba's cache tells the part was compiled:
# the same kernels as ``mimics.engine.compiling.warm_up._WITNESSES`` (tested), by module and name.
WITNESSES: dict[str, tuple[tuple[str, str], ...]] = {
    "index": (("mimics.engine.spatial_index", "_build_csr"),
              ("mimics.engine.robot_index", "_bucket"),
              ("mimics.engine.stall", "_record_and_screen")),
    "motion": (("mimics.engine.motion_checks", "_check_kernel"),
               ("mimics.engine.dynamics", "move_robots"),
               ("mimics.engine.helper_threads.threads", "_finish_and_wait"),
               ("mimics.engine.helper_threads.threads", "_join")),
    "ray": (("mimics.engine.ranging.ray_kernel", "_cast_rows"),
            ("mimics.engine.ranging.wall_index", "_near_lists"),
            ("mimics.engine.ranging.wall_occlusion", "cull_hidden"),
            ("mimics.engine.ranging.beam_fan", "beam_fans"),
            ("mimics.engine.ranging.ranger_noise", "_add_noise")),
    "still": (("mimics.engine.ranging.still_scans", "_settle"),
              ("mimics.engine.ranging.still_scans", "_pin")),
}
PARTS = tuple(WITNESSES)


class CannotTell(Exception):
    """Numba might look elsewhere than the locators mirrored here."""


def missing_parts() -> list[str] | None:
    """The parts whose witnesses Numba's cache lacks, or ``None`` when it cannot tell."""
    try:
        return [part for part in PARTS
                if not all(_has_index_file(module, name) for module, name in WITNESSES[part])]
    except CannotTell:
        return None


def source_file(module: str) -> str:
    """The file a module of mimics is loaded from, as its functions' code names it."""
    import mimics  # the package alone: its __init__ imports nothing heavy

    package = os.path.dirname(mimics.__file__ or "")
    return os.path.join(package, *module.split(".")[1:]) + ".py"


def cache_folder(module: str) -> str:
    """The folder Numba caches the kernels of ``module`` in (its first locator that applies)."""
    if (os.environ.get("NUMBA_CACHE_LOCATOR_CLASSES") or Path(".numba_config.yaml").exists()
            or not sys.platform.startswith("linux") or getattr(sys, "frozen", False)):
        raise CannotTell
    py_file = source_file(module)
    if not os.path.exists(py_file):
        raise CannotTell
    user_dir = os.environ.get("NUMBA_CACHE_DIR", "")
    candidates = [os.path.join(user_dir, _subpath(py_file))] if user_dir else []
    candidates.append(os.path.join(os.path.dirname(py_file), "__pycache__"))
    user_wide = os.getenv("XDG_CACHE_HOME", os.path.expanduser("~/.cache"))
    candidates.append(os.path.join(user_wide, "numba", _subpath(py_file)))
    for folder in candidates:
        if _writable(folder):
            return folder
    raise CannotTell  # Numba would not cache there at all


def index_file_pattern(module: str, name: str) -> re.Pattern[str]:
    """The names of a kernel's index files: ``module.qualname-LINE.pyXY.nbi``."""
    stem = f"{module.rsplit('.', 1)[-1]}.{name}".replace("<", "").replace(">", "")
    version = f"py{sys.version_info[0]}{sys.version_info[1]}{getattr(sys, 'abiflags', '')}"
    return re.compile(rf"{re.escape(stem)}-\d+\.{re.escape(version)}\.nbi")


def _has_index_file(module: str, name: str) -> bool:
    pattern = index_file_pattern(module, name)
    try:
        names = os.listdir(cache_folder(module))
    except OSError:
        return False
    return any(pattern.fullmatch(entry) for entry in names)


def _subpath(py_file: str) -> str:
    """Numba's ``get_suitable_cache_subpath``: the module's folder name and its path's SHA-1."""
    folder = os.path.dirname(os.path.abspath(py_file))
    return f"{os.path.split(folder)[-1]}_{hashlib.sha1(folder.encode()).hexdigest()}"


def _writable(folder: str) -> bool:
    """Numba's ``ensure_cache_path``: the folder is made and a file can be written in it."""
    try:
        os.makedirs(folder, exist_ok=True)
        tempfile.TemporaryFile(dir=folder).close()
    except OSError:
        return False
    return True
