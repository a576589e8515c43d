"""Algorithm and scenario references in battery files: paths made absolute, labels.

A reference is a built-in name, a path (made absolute relative to the battery
file) or, for algorithms, ``SCHEME:COMMAND`` (see
:func:`mimics.catalog.algorithm_scheme`), whose scheme makes its own paths
absolute and gives its label.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from mimics.native import NATIVE_SUFFIXES
from mimics.world.errors import MimicsError


def is_path(name: str) -> bool:
    """Whether a reference names a file (by its suffix or a path separator)."""
    return name.endswith((".py", ".toml", *NATIVE_SUFFIXES)) or "/" in name or "\\" in name


def resolve(name: str, base: Path) -> str:
    """A built-in name as is; a path made absolute relative to ``base``."""
    if not is_path(name):
        return name
    path = Path(name).expanduser()
    return str((path if path.is_absolute() else base / path).resolve())


def resolve_algorithm(name: str, base: Path) -> str:
    """As :func:`resolve`; a ``SCHEME:COMMAND`` algorithm's paths made absolute by its scheme."""
    from mimics.catalog import algorithm_scheme

    scheme = algorithm_scheme(name)
    if scheme is None:
        return resolve(name, base)
    provider, command = scheme
    return f"{provider.name}:{provider.resolve(command, base)}"


def algorithm_label(ref: str) -> str:
    """An algorithm's name in run listings and folder names."""
    from mimics.catalog import algorithm_scheme

    scheme = algorithm_scheme(ref)
    if scheme is not None:
        provider, command = scheme
        return str(provider.label(command))
    return Path(ref).stem if is_path(ref) else ref


def check_algorithms(value: Any, base: Path, fail: Any) -> tuple[str, ...]:
    """The battery's algorithm references, made absolute. A ``.py`` file is checked for
    existence only: it is imported, checked and run inside the workers alone, so that a
    broken or hostile submission costs its own runs, never the battery."""
    from mimics.catalog import find_algorithm
    from mimics.engine.user_code import controller_from

    if isinstance(value, str):
        value = [value]
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise fail(f"[battery] algorithms: expected a non-empty list of names or .py paths, got "
                   f"{value!r}")
    refs: list[str] = []
    for name in value:
        try:
            ref = resolve_algorithm(name, base)
            if ref.endswith(".py"):  # a submission: only its name here; it loads in a worker
                if not Path(ref).is_file():
                    raise MimicsError(f"algorithm file {ref} does not exist")
            else:
                label, module = find_algorithm(ref)
                controller_from(module, label)
        except MimicsError as exc:
            raise fail(f"[battery] algorithms: {exc}") from None
        if ref in refs:
            raise fail(f"[battery] algorithms: {name!r} is listed twice")
        refs.append(ref)
    return tuple(refs)
