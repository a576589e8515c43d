"""What ``ros:`` and ``ros2:`` algorithms share: the command, the node's process, the scheme.

A controller-node algorithm is written ``SCHEME:[--names=SET] PROGRAM [ARGS...]``
(``ros:`` for ROS 1, :mod:`mimics.interfaces.ros.node_algorithm`; ``ros2:``
for ROS 2, :mod:`mimics.interfaces.ros2.node_algorithm`). Everything here
is free of any transport: parsing and quoting the command, the node's
command line (``{robots}``, ``{seed}``... replaced), starting and stopping
its process (SIGINT, then SIGKILL; the kernel kills it if this process
dies), closing a run's node and bridge when the process exits, the defaults
``mimics run`` and battery files set, and the scheme object the catalog
loads. A transport supplies only the controller's ``reset``: its bridge,
and how the node finds it.
"""

from __future__ import annotations

import atexit
import multiprocessing.util
import os
import re
import shlex
import shutil
import signal
import subprocess
from abc import abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, ClassVar, Protocol

from mimics.engine.user_code import Controller, UserFailure
from mimics.interfaces.ros.names import NAME_SETS
from mimics.world.errors import AlgorithmError, MimicsError

if TYPE_CHECKING:
    import numpy as np

    from mimics.engine.outcome import RunResult
    from mimics.engine.simulation import Simulation

NAMES_OPTION = "--names="


@dataclass(frozen=True)
class NodeKind:
    """What differs between ROS 1 and ROS 2 nodes in a command.

    Attributes:
        scheme: the algorithm's scheme, ``"ros"`` or ``"ros2"`` (also the label's prefix).
        node_text: what PROGRAM must be, for error messages.
        python: the interpreter that runs a ``.py`` node.
    """

    scheme: str
    node_text: str
    python: Callable[[], str]


@dataclass(frozen=True)
class NodeCommand:
    """A controller node's program (absolute) and arguments, and the bridge's name set
    (None: the process's default, :data:`DEFAULTS`). A subclass sets :attr:`kind`."""

    kind: ClassVar[NodeKind]
    program: Path
    args: tuple[str, ...]
    names: str | None = None

    @classmethod
    def parse(cls, text: str, base: Path) -> NodeCommand:
        """``[--names=SET] PROGRAM [ARGS...]``, PROGRAM a file relative to ``base`` or a
        name on ``PATH``.

        Raises:
            AlgorithmError: naming the algorithm and what was expected.
        """
        scheme, what = cls.kind.scheme, cls.kind.node_text
        where = f"algorithm '{scheme}:{text}'"
        try:
            words = shlex.split(text)
        except ValueError as exc:
            raise AlgorithmError(f"{where}: {exc} (expected {scheme}:PROGRAM [ARGS...])"
                                 ) from None
        names = None
        while words and words[0].startswith("--"):
            option = words.pop(0)
            if not option.startswith(NAMES_OPTION):
                raise AlgorithmError(f"{where}: unknown option {option!r} before the program "
                                     f"(expected {NAMES_OPTION}SET, SET one of "
                                     f"{', '.join(NAME_SETS)})")
            names = option[len(NAMES_OPTION):]
            if names not in NAME_SETS:
                raise AlgorithmError(f"{where}: {NAMES_OPTION}: expected one of "
                                     f"{', '.join(NAME_SETS)}, got {names!r}")
        if not words:
            raise AlgorithmError(f"{where}: expected {scheme}:PROGRAM [ARGS...], PROGRAM "
                                 f"{what}")
        path = Path(words[0]).expanduser()
        found = shutil.which(words[0]) if len(path.parts) == 1 else None
        if not path.is_absolute():
            path = base / path
        if path.is_file():
            program = path.resolve()
        elif found is not None:
            program = Path(found)
        else:
            raise AlgorithmError(f"{where}: no program {str(path)!r} (expected {what})")
        if program.suffix != ".py" and not os.access(program, os.X_OK):
            raise AlgorithmError(f"{where}: {str(program)!r} is neither a .py file nor "
                                 "executable (chmod +x it, or build the node)")
        return cls(program, tuple(words[1:]), names)

    @property
    def text(self) -> str:
        """The command as an algorithm reference takes it (after ``SCHEME:``)."""
        options = [] if self.names is None else [f"{NAMES_OPTION}{self.names}"]
        return " ".join(_quoted(word) for word in (*options, str(self.program), *self.args))

    @property
    def label(self) -> str:
        """The algorithm's display name: the scheme, ``-`` and the program's stem."""
        return f"{self.kind.scheme}-{self.program.stem}"

    def argv(self, **values: int) -> list[str]:
        """The command line of the node for one run: ``{name}`` in ARGS replaced by
        ``values[name]`` (``robots``, ``seed``, ROS 2's ``domain``)."""
        args = list(self.args)
        for name, value in values.items():
            args = [arg.replace(f"{{{name}}}", str(value)) for arg in args]
        start = [self.kind.python()] if self.program.suffix == ".py" else []
        return [*start, str(self.program), *args]


def _quoted(word: str) -> str:
    """``word`` quoted for the shell only if it must be (``{robots}`` stays as it is)."""
    return word if _PLAIN.fullmatch(word) else shlex.quote(word)


_PLAIN = re.compile(r"[\w@%+=:,./{}-]+")


class Bridge(Protocol):
    """What a node run needs of its transport's bridge (an observer of the run)."""

    def on_start(self, sim: Simulation) -> None: ...

    def on_step(self, sim: Simulation) -> None: ...

    def on_end(self, sim: Simulation, result: RunResult) -> None: ...

    def close(self) -> None: ...


class NodeRun:
    """One run's node process and bridge; an observer that publishes and cleans up."""

    current: ClassVar[NodeRun | None] = None  # at most one per process (rospy has one node)

    def __init__(self, bridge: Bridge, argv: list[str], environment: dict[str, str],
                 released: Callable[[], None] | None = None) -> None:
        """Start the node ``argv`` with ``environment`` added to this process's; ``released``
        is called last when the run closes (after the bridge)."""
        from mimics.interfaces.child_processes import dying_with_parent

        self.bridge = bridge
        self.argv = argv
        self._released = released
        self.node = subprocess.Popen(dying_with_parent(argv), env={**os.environ, **environment})
        NodeRun.current = self

    def on_start(self, sim: Simulation) -> None:
        self.bridge.on_start(sim)

    def on_step(self, sim: Simulation) -> None:
        self.bridge.on_step(sim)

    def on_end(self, sim: Simulation, result: RunResult) -> None:
        self.bridge.on_end(sim, result)
        self.close()

    def check_node(self) -> None:
        """Raise if the node has exited (while mimics waits for it to connect)."""
        code = self.node.poll()
        if code is not None:
            raise MimicsError(f"the controller node {shlex.join(self.argv)!r} "
                              f"exited with status {code} before it connected")

    def close(self) -> None:
        from mimics.interfaces.ros.private_master import stop_process

        if NodeRun.current is self:
            NodeRun.current = None
            stop_process(self.node, signal.SIGINT)
            self.bridge.close()
            if self._released is not None:
                self._released()


def close_current() -> None:
    """Stop the node and withdraw the bridge of the run still open in this process, if any."""
    if NodeRun.current is not None:
        NodeRun.current.close()


atexit.register(close_current)
# a multiprocessing child (a battery worker) ends with os._exit, skipping atexit
multiprocessing.util.Finalize(None, close_current, exitpriority=200)


@dataclass
class NodeDefaults:
    """The bridge settings of ``ros:`` and ``ros2:`` runs in this process.

    ``mimics run --ros-timeout`` sets ``timeout`` and ``timeout_option``, and
    so does a battery file's ``ros_timeout`` (:meth:`NodeScheme.configure`);
    ``--ros-names`` (or ``SCHEME:--names=stage``) sets ``names``; elsewhere
    (the Python API) the defaults hold and time-out messages cite no option.
    """

    timeout: float = 10.0
    timeout_option: str | None = None
    names: str = "mimics"


DEFAULTS = NodeDefaults()


class NodeController(Controller):
    """The engine's controller of a node algorithm: references from a node it starts
    in :meth:`reset` (the transport's part)."""

    def __init__(self, command: NodeCommand) -> None:
        self.command = command
        self.name = command.label
        self._references: Controller | None = None

    @abstractmethod
    def reset(self, sim: Simulation) -> list[UserFailure]:
        """Publish the run's topics, start the node and wait for it; set ``_references``."""

    def _waited(self, run: NodeRun, bridge: Any, active: np.ndarray) -> None:
        """Wait for the node to connect; on failure (it exited, time-out) close the run."""
        try:
            bridge.wait_for_nodes(active, check=run.check_node)
        except BaseException:
            run.close()
            raise

    def compute(self, sim: Simulation, ids: np.ndarray) -> list[UserFailure]:
        if self._references is None:
            raise RuntimeError("compute() before reset()")
        return self._references.compute(sim, ids)


class NodeScheme:
    """A node algorithm scheme (``ros:``, ``ros2:``), as the catalog uses it."""

    def __init__(self, command: type[NodeCommand],
                 controller: Callable[[Any], NodeController]) -> None:
        self.command = command
        self.controller = controller
        self.name = command.kind.scheme

    def resolve(self, command: str, base: Path) -> str:
        """The command with its program made absolute (relative to ``base``)."""
        return self.command.parse(command, base).text

    def label(self, command: str) -> str:
        """The display name, without checking the program (the scheme, ``-``, its stem)."""
        try:
            words = shlex.split(command)
        except ValueError:
            words = command.split()
        words = [word for word in words if not word.startswith("--")][:1]  # options first
        return f"{self.name}-{Path(words[0]).stem}" if words else self.name

    def configure(self, timeout: float | None, option: str | None) -> None:
        """A battery's ``ros_timeout`` (None: the default, 10 s), cited as ``option``."""
        DEFAULTS.timeout = NodeDefaults.timeout if timeout is None else timeout
        DEFAULTS.timeout_option = option if timeout is not None else None

    def algorithm(self, command: str) -> tuple[str, Any]:
        """The display name and a fresh controller (a relative program: from the current
        folder)."""
        parsed = self.command.parse(command, Path.cwd())
        return parsed.label, self.controller(parsed)
