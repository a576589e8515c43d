"""How far a battery keeps each run apart: ``[battery] isolation`` and ``sandbox``.

``isolation = "worker"`` (the default, the fastest): a worker process runs one
run after another; user modules are imported afresh for each run, the libraries
are not, so a submission that patches a library (NumPy, mimics, ``builtins``)
changes the runs that follow it in that worker. ``isolation = "run"``: every run
gets a process of its own, forked from the fork server (which imported the engine
but never ran user code) and ended after that one run.

``sandbox = "bwrap"`` (needs ``isolation = "run"``, which it implies when the file
does not say): each run's process runs under bubblewrap
(:mod:`mimics.batteries.sandbox`): the file system read-only, the submissions'
folders and the battery folder hidden but for the run's own copy of its file and
its own run folder, no network.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from mimics.world.errors import MimicsError

ISOLATIONS = ("worker", "run")
SANDBOXES = ("none", "bwrap")
DEFAULT_ISOLATION = "worker"


@dataclass(frozen=True)
class Containment:
    """What a local executor needs to keep runs apart.

    Attributes:
        isolation: ``"worker"`` or ``"run"``.
        sandbox: ``""`` (none) or ``"bwrap"``.
        hidden: folders a sandboxed run must not see (the battery folder, the
            folders of the battery's algorithm files); each run's own file's folder
            is hidden too.
        visible: files inside those folders a run must still read (scenario files).
    """

    isolation: str = DEFAULT_ISOLATION
    sandbox: str = ""
    hidden: tuple[str, ...] = ()
    visible: tuple[str, ...] = ()

    @property
    def one_run_per_process(self) -> bool:
        """Whether each run gets a fresh process."""
        return self.isolation == "run" or bool(self.sandbox)


def parse_isolation(table: dict[str, Any], algorithms: tuple[str, ...],
                    fail: Callable[[str], MimicsError]) -> tuple[str, str]:
    """``[battery] isolation`` and ``sandbox`` from a battery file's table.

    Returns:
        ``(isolation, sandbox)``, sandbox ``""`` for none.
    """
    sandbox = table.get("sandbox", "none")
    if sandbox not in SANDBOXES:
        raise fail(f"[battery] sandbox: expected \"none\" or \"bwrap\", got {sandbox!r}")
    sandbox = "" if sandbox == "none" else sandbox
    isolation = table.get("isolation", "run" if sandbox else DEFAULT_ISOLATION)
    if isolation not in ISOLATIONS:
        raise fail(f"[battery] isolation: expected \"worker\" or \"run\", got {isolation!r}")
    check_combination(isolation, sandbox, algorithms, fail, "[battery] ")
    return isolation, sandbox


def check_combination(isolation: str, sandbox: str, algorithms: tuple[str, ...],
                      fail: Callable[[str], MimicsError], where: str = "") -> None:
    """A sandbox needs a process per run and no ``ros:`` algorithm (they need the network)."""
    if sandbox and isolation != "run":
        raise fail(f"{where}sandbox = \"{sandbox}\" needs isolation = \"run\" (a process per "
                   f"run), got isolation = \"{isolation}\"")
    if sandbox and any(a.startswith(("ros:", "ros2:")) for a in algorithms):
        raise fail(f"{where}sandbox = \"{sandbox}\": not with ros: or ros2: algorithms (the "
                   "sandbox has no network, and a ROS node needs one)")
    from mimics.native import NATIVE_SUFFIXES

    native = [a for a in algorithms if a.endswith(NATIVE_SUFFIXES)]
    if sandbox and native:
        raise fail(f"{where}sandbox = \"{sandbox}\": only for built-in and .py algorithms, "
                   f"not {native[0]} (a C/C++ file is compiled where the sandbox cannot "
                   "write)")


def with_options(spec: Any, isolation: str | None, sandbox: str | None) -> Any:
    """``spec`` with the command line's ``--isolation`` and ``--sandbox`` applied.

    Raises:
        MimicsError: an unknown value, or a sandbox without ``run`` isolation.
    """
    from dataclasses import replace

    if isolation is not None and isolation not in ISOLATIONS:
        raise MimicsError(f"--isolation: expected worker or run, got {isolation!r}")
    if sandbox is not None and sandbox not in SANDBOXES:
        raise MimicsError(f"--sandbox: expected none or bwrap, got {sandbox!r}")
    new_sandbox = spec.sandbox if sandbox is None else ("" if sandbox == "none" else sandbox)
    new_isolation = isolation or ("run" if new_sandbox and sandbox else spec.isolation)
    check_combination(new_isolation, new_sandbox, spec.algorithms, MimicsError,
                      "--isolation, --sandbox: ")
    return replace(spec, isolation=new_isolation, sandbox=new_sandbox)


def refuse_dask(spec: Any) -> None:
    """A process per run and the sandbox are for local workers: refuse them with ``--dask``.

    Raises:
        MimicsError: the spec has ``isolation = "run"`` or a sandbox.
    """
    if spec.isolation != "worker" or spec.sandbox:
        raise MimicsError("--dask: this battery has isolation = \"run\" or a sandbox, which "
                          "are for local workers; run it without --dask")


def containment_of(spec: Any, battery_folder: str | Path) -> Containment:
    """The containment a battery's spec asks for, its hidden folders resolved."""
    if not spec.sandbox:
        return Containment(spec.isolation)
    hidden = {str(Path(battery_folder).resolve())}
    hidden.update(str(Path(a).resolve().parent) for a in spec.algorithms if a.endswith(".py"))
    visible = tuple(str(Path(s.ref).resolve()) for s in spec.scenarios
                    if s.ref.endswith((".py", ".toml")))
    return Containment(spec.isolation, spec.sandbox, tuple(sorted(hidden)), visible)
