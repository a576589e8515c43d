"""Algorithms defined in a notebook, for batteries: the ``pickle:`` algorithm scheme.

A battery names its algorithms by text (built-in names, file paths), stored in
its database and sent to its workers, which run in other processes, perhaps on
other machines (Dask). A function or class defined in a notebook cell has no
file to name, so :func:`algorithm_ref` pickles it by value (cloudpickle, with
the cell's globals it uses) into the text itself::

    pickle:LABEL:FINGERPRINT:BASE64

``LABEL`` is its name in run listings and folder names, ``FINGERPRINT`` a hash
of its source (of its pickle when the source cannot be read) that tells a
changed algorithm from the same one defined again, and ``BASE64`` the pickle
that every worker loads, whatever carries the task. The scheme is registered as
the entry point ``pickle`` of ``mimics.algorithm_schemes`` (pyproject.toml).

A ``pickle:`` text runs code when loaded, as a ``.py`` algorithm does: load
batteries only from people whose code you would run.

>>> def step(robot):
...     return 0.5, 0.0
>>> ref = algorithm_ref(step)
>>> ref.startswith("pickle:step:"), SCHEME.label(ref.removeprefix("pickle:"))
(True, 'step')
>>> label, loaded = SCHEME.algorithm(ref.removeprefix("pickle:"))
>>> label, loaded(None)
('step', (0.5, 0.0))
"""

from __future__ import annotations

import base64
import hashlib
import inspect
import pickle
import re
from pathlib import Path
from typing import Any

from mimics.world.errors import AlgorithmError

PREFIX = "pickle:"
#: ipykernel's temporary cell files carry the kernel's process id: not part of the code.
_KERNEL_FILES = re.compile(rb"ipykernel_\d+")


def is_inline_algorithm(value: Any) -> bool:
    """Whether ``value`` is an algorithm object (a function or class), not a name."""
    return callable(value) and not isinstance(value, str | Path)


def algorithm_ref(algorithm: Any) -> str:
    """The ``pickle:`` text of a function or class (pickled by value).

    Raises:
        AlgorithmError: it cannot be pickled (naming it and why).
    """
    label = _label(algorithm)
    try:
        data = _dumps(algorithm)
    except Exception as exc:  # whatever the object holds that cannot travel
        raise AlgorithmError(f"algorithm {label!r}: cannot be sent to the battery's workers "
                             f"({type(exc).__name__}: {exc}); define what it uses in the "
                             "notebook or in a .py file") from None
    return f"{PREFIX}{label}:{_fingerprint(algorithm, data)}:" \
           f"{base64.b64encode(data).decode('ascii')}"


def without_pickles(ref: str) -> str:
    """``ref`` without its pickle (``pickle:LABEL:FINGERPRINT``): what tells two
    algorithms apart, the same for the same code defined again."""
    if not ref.startswith(PREFIX):
        return ref
    return ref.rsplit(":", 1)[0]


def _label(algorithm: Any) -> str:
    name = str(getattr(algorithm, "__name__", type(algorithm).__name__))
    cleaned = re.sub(r"[^A-Za-z0-9_.-]+", "_", name).strip("_")  # "<lambda>" -> "lambda"
    return cleaned or "algorithm"


def _dumps(algorithm: Any) -> bytes:
    try:
        import cloudpickle
    except ImportError:  # by reference only: enough for what a module defines
        return pickle.dumps(algorithm)
    return bytes(cloudpickle.dumps(algorithm))


def _fingerprint(algorithm: Any, data: bytes) -> str:
    try:
        text = inspect.getsource(algorithm).encode()
    except (OSError, TypeError):  # no source to read: the pickle, kernel files masked
        text = _KERNEL_FILES.sub(b"ipykernel", data)
    return hashlib.sha256(text).hexdigest()[:16]


class PickleScheme:
    """The ``pickle:`` algorithm scheme, as the catalog uses it."""

    name = "pickle"

    def resolve(self, command: str, base: Path) -> str:
        """The command as it is (it names no file)."""
        return command

    def label(self, command: str) -> str:
        """The algorithm's name, before its first colon."""
        return command.split(":", 1)[0] or "algorithm"

    def algorithm(self, command: str) -> tuple[str, Any]:
        """The display name and the function or class, unpickled.

        Raises:
            AlgorithmError: a malformed text, or a pickle that does not load here.
        """
        label, _, rest = command.partition(":")
        _, _, encoded = rest.partition(":")
        try:
            loaded = pickle.loads(base64.b64decode(encoded.encode("ascii"), validate=True))
        except Exception as exc:  # a cut text, or a module missing in this environment
            raise AlgorithmError(f"algorithm {label!r} (defined in a notebook): cannot be "
                                 f"loaded here ({type(exc).__name__}: {exc})") from None
        return label, loaded


SCHEME = PickleScheme()
