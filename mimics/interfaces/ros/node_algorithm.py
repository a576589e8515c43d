"""``ros:`` algorithms: a ROS controller node, started by mimics, drives a run.

An algorithm written ``ros:PROGRAM [ARGS...]`` (``mimics run``, a battery
file's ``algorithms``, the Python API) is a ROS 1 controller node: a rospy
``.py`` file (run with the system's Python, where Debian puts rospy) or an
executable (a roscpp node, say). For each run, mimics

1. starts this process's private master if it has none yet
   (:mod:`~mimics.interfaces.ros.private_master`) and joins it as the node
   ``/mimics`` (once per process, as rospy allows);
2. publishes the run's topics (the bridge of ``mimics ros``), starts the
   node with ``{robots}`` and ``{seed}`` in ARGS replaced by the run's robot
   count and seed (also given as ``MIMICS_ROBOTS`` and ``MIMICS_SEED``) and
   waits until it listens to each robot's topics and publishes commands;
3. runs in lockstep (each step waits for every active robot's command), so
   the run is as deterministic as the node, and a battery of such runs gives
   the same results on any number of workers;
4. stops the node when the run ends (SIGINT, then SIGKILL) and withdraws
   the run's topics. The kernel kills the node and the master if the process
   dies first (a battery worker past its time limit, say).

Options of the bridge may come before PROGRAM: ``ros:--names=stage
PROGRAM [ARGS...]`` publishes ``stage_ros``' names
(:mod:`~mimics.interfaces.ros.names`), for a node written for Stage; in a
battery file that is the way to choose them (``mimics run`` also has
``--ros-names``, which the algorithm's own option overrides).

The entry point ``ros`` of the group ``mimics.algorithm_schemes``
(``pyproject.toml``) is :data:`SCHEME`: the catalog finds it there, so that
the layers below the interfaces never import ROS.
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
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.user_code import Controller, UserFailure
from mimics.interfaces.ros.names import NAME_SETS
from mimics.world.errors import AlgorithmError, MimicsError

if TYPE_CHECKING:
    from mimics.engine.outcome import RunResult
    from mimics.engine.simulation import Simulation
    from mimics.interfaces.ros.bridge import RosBridge


def system_python() -> str:
    """The Python that runs rospy nodes: the system's (Debian's rospy lives there)."""
    return shutil.which("python3", path="/usr/bin") or sys.executable


NAMES_OPTION = "--names="


@dataclass(frozen=True)
class NodeCommand:
    """A controller node's program (absolute) and arguments, and the bridge's name set
    (None: the process's default, :data:`DEFAULTS`)."""

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
        where = f"algorithm 'ros:{text}'"
        try:
            words = shlex.split(text)
        except ValueError as exc:
            raise AlgorithmError(f"{where}: {exc} (expected ros:PROGRAM [ARGS...])") from None
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
            raise AlgorithmError(f"{where}: expected ros:PROGRAM [ARGS...], PROGRAM a rospy "
                                 ".py file or an executable ROS node")
        path = Path(words[0]).expanduser()
        found = shutil.which(words[0]) if len(path.parts) == 1 else None
        if not path.is_absolute():
            path = base / path
        if path.is_file():
            program = path.resolve()
        elif found is not None:
            program = Path(found)
        else:
            raise AlgorithmError(f"{where}: no program {str(path)!r} (expected a rospy .py "
                                 "file or an executable ROS node)")
        if program.suffix != ".py" and not os.access(program, os.X_OK):
            raise AlgorithmError(f"{where}: {str(program)!r} is neither a .py file nor "
                                 "executable (chmod +x it, or build the node)")
        return cls(program, tuple(words[1:]), names)

    @property
    def text(self) -> str:
        """The command as an algorithm reference takes it (after ``ros:``)."""
        options = [] if self.names is None else [f"{NAMES_OPTION}{self.names}"]
        return " ".join(_quoted(word) for word in (*options, str(self.program), *self.args))

    @property
    def label(self) -> str:
        """The algorithm's display name: ``ros-`` and the program's stem."""
        return f"ros-{self.program.stem}"

    def argv(self, robots: int, seed: int) -> list[str]:
        """The command line of the node for one run."""
        args = [arg.replace("{robots}", str(robots)).replace("{seed}", str(seed))
                for arg in self.args]
        start = [system_python()] if self.program.suffix == ".py" else []
        return [*start, str(self.program), *args]


def _quoted(word: str) -> str:
    """``word`` quoted for the shell only if it must be (``{robots}`` stays as it is)."""
    return word if _PLAIN.fullmatch(word) else shlex.quote(word)


_PLAIN = re.compile(r"[\w@%+=:,./{}-]+")


class _NodeRun:
    """One run's node process and bridge; an observer that publishes and cleans up."""

    current: _NodeRun | None = None  # at most one per process: rospy has one node

    def __init__(self, bridge: RosBridge, argv: list[str], robots: int, seed: int) -> None:
        from mimics.interfaces.child_processes import dying_with_parent

        self.bridge = bridge
        self.argv = argv
        self.node = subprocess.Popen(dying_with_parent(argv), env={
            **os.environ, "MIMICS_ROBOTS": str(robots), "MIMICS_SEED": str(seed)})
        _NodeRun.current = self

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

        if _NodeRun.current is self:
            _NodeRun.current = None
            stop_process(self.node, signal.SIGINT)
            self.bridge.close()


@atexit.register
def _close_current() -> None:
    if _NodeRun.current is not None:
        _NodeRun.current.close()


# a multiprocessing child (a battery worker) ends with os._exit, skipping atexit
multiprocessing.util.Finalize(None, _close_current, exitpriority=200)


@dataclass
class NodeDefaults:
    """The bridge settings of ``ros:`` runs in this process.

    ``mimics run --ros-timeout`` sets ``timeout`` and ``timeout_option``, and
    so does a battery file's ``ros_timeout`` (:meth:`RosScheme.configure`);
    ``--ros-names`` (or ``ros:--names=stage``) sets ``names``; elsewhere (the
    Python API) the defaults hold and time-out messages cite no option.
    """

    timeout: float = 10.0
    timeout_option: str | None = None
    names: str = "mimics"


DEFAULTS = NodeDefaults()


class NodeController(Controller):
    """The engine's controller of a ``ros:`` algorithm: references from a node it starts."""

    def __init__(self, command: NodeCommand) -> None:
        self.command = command
        self.name = command.label
        self._references: Controller | None = None

    def reset(self, sim: Simulation) -> list[UserFailure]:
        from mimics.interfaces.ros.bridge import BridgeOptions, RosBridge, join_ros
        from mimics.interfaces.ros.private_master import private_master

        # lockstep: a run as deterministic as the node
        options = BridgeOptions(timeout=DEFAULTS.timeout, timeout_option=DEFAULTS.timeout_option,
                                names=self.command.names or DEFAULTS.names)
        _close_current()  # a run that ended without on_end (it raised) leaves its node
        private_master()
        join_ros()  # rospy importable from here on
        from mimics.interfaces.ros.inbox import Inbox
        from mimics.interfaces.ros.references import RosReferences

        state = sim.state
        inbox = Inbox(state.n, lockstep=True, timeout=options.timeout)
        references = RosReferences(inbox, sim.scenario.stages[:, 2], options.timeout,
                                   options.timeout_option)
        self._references = references.controller()
        bridge = RosBridge(sim, inbox, options)
        references.publishers = bridge.commands.publishers_connected
        references.names = bridge.names
        run = _NodeRun(bridge, self.command.argv(state.n, sim.seed), state.n, sim.seed)
        try:
            bridge.wait_for_nodes(np.flatnonzero(state.active), check=run.check_node)
        except BaseException:
            run.close()
            raise
        sim.observers.append(run)
        return self._references.reset(sim)

    def compute(self, sim: Simulation, ids: np.ndarray) -> list[UserFailure]:
        if self._references is None:
            raise RuntimeError("compute() before reset()")
        return self._references.compute(sim, ids)


class RosScheme:
    """The ``ros:`` algorithm scheme, as the catalog uses it."""

    name = "ros"

    def resolve(self, command: str, base: Path) -> str:
        """The command with its program made absolute (relative to ``base``)."""
        return NodeCommand.parse(command, base).text

    def label(self, command: str) -> str:
        """The display name, without checking the program (``ros-`` and its stem)."""
        try:
            words = shlex.split(command)
        except ValueError:
            words = command.split()
        words = [word for word in words if not word.startswith("--")][:1]  # options first
        return f"ros-{Path(words[0]).stem}" if words else "ros"

    def configure(self, timeout: float | None, option: str | None) -> None:
        """A battery's ``ros_timeout`` (None: the default, 10 s), cited as ``option``."""
        DEFAULTS.timeout = NodeDefaults.timeout if timeout is None else timeout
        DEFAULTS.timeout_option = option if timeout is not None else None

    def algorithm(self, command: str) -> tuple[str, Any]:
        """The display name and a fresh controller (a relative program: from the current folder)."""
        parsed = NodeCommand.parse(command, Path.cwd())
        return parsed.label, NodeController(parsed)


SCHEME = RosScheme()
