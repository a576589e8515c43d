"""Running user algorithms: the contract, timing, and containment of their failures.

An algorithm is any of:

* a function ``step(robot) -> (speed_ref, heading_ref)``, with an optional
  ``reset(robot)`` beside it in the same module, called once per robot before
  the first step;
* a class with ``step(self, robot)`` (and optional ``reset(self, robot)``):
  one instance per robot, so ``self`` is that robot's private memory;
* a team function ``team_step(team) -> (speed_refs, heading_refs)`` (arrays
  over ``team.ids``), or a class with ``team_step``, for vectorised teams. A
  function passed on its own is a team function when it is named
  ``team_step``, a per-robot one otherwise.

``speed_ref`` is in m/s, ``heading_ref`` an absolute heading in radians. Each
per-robot call is timed on its own, one robot after another.
"""

from __future__ import annotations

import inspect
import math
import time
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np

from mimics.engine.user_code.failure_places import (
    failure_place,
    first_line,
    return_lines,
    user_traceback,
    where_of,
)
from mimics.engine.user_code.robot_view import Robot, Team
from mimics.engine.user_code.view_hub import hub_of
from mimics.engine.user_code.watchdog import StepTimeout, blame, raise_in_thread
from mimics.world.errors import AlgorithmError

if TYPE_CHECKING:
    from mimics.engine.user_code.world_access import SimulationParts


@dataclass(frozen=True)
class UserFailure:
    """An exception or invalid output of user code.

    ``where`` is the place in the user's code (``"my_algo.py:7"``; "" when unknown)
    and ``line`` that line's source text; ``traceback`` holds the user's frames only.
    """

    robot: int  # -1 when a team call failed as a whole
    time: float
    kind: str  # exception class name, or "InvalidOutput"
    message: str
    traceback: str
    where: str = ""
    line: str = ""
    # the exception itself, for mimics.simulate to raise with the user's frames
    exception: BaseException | None = field(default=None, repr=False, compare=False)

    def describe(self) -> str:
        """``"AttributeError in robot 0 at t=0 s, my_algo.py:7: message"``, then the source
        line on a second line when known."""
        who = "the team algorithm" if self.robot < 0 else f"robot {self.robot}"
        at = f", {self.where}" if self.where else ""
        message = self.message.removeprefix(f"{who}: ")  # "robot 2: step() returned..."
        text = f"{self.kind} in {who} at t={self.time:g} s{at}: {message}"
        return f"{text}\n    {self.line}" if self.line else text


class Controller(ABC):
    """Drives a set of robots from an algorithm; subclasses wrap each calling form."""

    name: str = "algorithm"
    is_team: bool = False

    def reset(self, sim: SimulationParts) -> list[UserFailure]:
        """Prepare for a new run; returns failures of user reset hooks."""
        return []

    @abstractmethod
    def compute(self, sim: SimulationParts, ids: np.ndarray) -> list[UserFailure]:
        """Write references for robots ``ids`` into ``sim.state.reference``."""

    def prepare_interrupt(self) -> None:
        """Make :meth:`interrupt` possible (called when a run with a wall limit starts)."""
        return None  # Python code needs nothing: an exception can be raised into it

    def interrupt(self, thread_id: int) -> None:
        """Stop the user code running in thread ``thread_id`` (from the wall-limit watchdog):
        a :class:`~mimics.engine.user_code.watchdog.StepTimeout` raised into Python code."""
        raise_in_thread(thread_id)


def failure_from_exception(robot: int, now: float, exc: BaseException) -> UserFailure:
    """The failure of a user call that raised ``exc``, placed at the user's innermost line."""
    place = failure_place(exc)
    return UserFailure(robot, now, type(exc).__name__, first_line(exc), user_traceback(exc),
                       str(place) if place else "", place.text if place else "", exc)


def invalid_output(robot: int, now: float, message: str, step: Any = None,
                   output: Any = None) -> UserFailure:
    """An invalid output of ``step``, placed at the ``return`` lines that can have given it."""
    where, line = where_of(return_lines(step, output)) if step is not None else ("", "")
    return UserFailure(robot, now, "InvalidOutput", message, "", where, line)


#: The types a step's references usually are: checked by identity, the fast way.
_PLAIN = frozenset({float, int, np.float64, np.float32, np.int64})


def _refuse_text_and_truth(*values: Any) -> None:
    """Raise TypeError for a text or a truth value (or an array of them): ``float("1")``
    and ``float(True)`` succeed, but a step returning them has a bug, not a reference."""
    for value in values:
        kind = getattr(getattr(value, "dtype", None), "kind", "")
        if isinstance(value, str | bytes | bytearray | bool | np.bool_) or kind in ("b", "U",
                                                                                  "S", "O"):
            raise TypeError(f"not a number: {value!r}")


def _not_two_numbers(robot: int, now: float, output: Any, step: Any) -> UserFailure:
    return invalid_output(robot, now, f"robot {robot}: step() must return (speed_ref, "
                                      f"heading_ref), two numbers; got {_shown(output)}",
                          step, output)


def _not_finite(robot: int, now: float, speed: float, heading: float, step: Any,
                output: Any) -> UserFailure:
    return invalid_output(robot, now, f"robot {robot}: step() returned a non-finite reference "
                                      f"(speed_ref={speed}, heading_ref={heading})", step, output)


def _shown(output: Any) -> str:
    """An output as a student reads it: ``0.5 (a float)`` rather than ``np.float64(0.5)``."""
    if output is None:
        return "None (it ended without returning a value)"
    text = repr(output.item() if isinstance(output, np.generic) else output)
    text = text if len(text) <= 200 else text[:197] + "..."
    return f"{text} (a {type(output).__name__})"


class PerRobotController(Controller):
    """Calls ``step(robot)`` for each robot in turn, each call timed on its own."""

    def __init__(self, name: str, step: Any = None, reset: Any = None,
                 factory: type | None = None) -> None:
        self.name = name
        self._step_fn = step
        self._reset_fn = reset
        self._factory = factory
        self._instances: list[Any] = []
        self._robots: list[Robot] = []

    def reset(self, sim: SimulationParts) -> list[UserFailure]:
        failures = []
        hub = hub_of(sim)
        hub.refresh()
        self._robots = [Robot(sim, i) for i in range(sim.state.n)]
        self._instances = []
        for robot in self._robots:
            try:
                instance = self._factory() if self._factory is not None else None
                self._instances.append(instance)
                hook = getattr(instance, "reset", None) if instance is not None else self._reset_fn
                if hook is not None:
                    hook(robot)
            except Exception as exc:  # user code: contain everything it raises
                self._instances.append(None)
                failures.append(failure_from_exception(robot.id, sim.state.time, exc))
            except StepTimeout as stop:  # past the wall limit: say whose call it was
                blame(stop, robot.id, "reset()")
                raise
        return failures

    def compute(self, sim: SimulationParts, ids: np.ndarray) -> list[UserFailure]:
        failures = []
        hub_of(sim).refresh()  # the views' mirrors: this step's values, copied once
        state = sim.state
        now = state.time
        clock = time.perf_counter
        instances, robots = self._instances, self._robots
        # Gathered in lists and written once at the end: a NumPy row write per
        # robot costs more than the call of a simple algorithm. User code never
        # sees references or call times, so nothing can tell the difference.
        times: list[float] = []
        done: list[int] = []
        speeds: list[float] = []  # two flat lists: NumPy reads them faster than pairs
        headings: list[float] = []
        isfinite = math.isfinite
        plain = self._factory is None  # one function for every robot (the usual case)
        for i in ids.tolist():
            if plain:
                step = self._step_fn
            else:
                instance = instances[i]
                step = instance.step if instance is not None else self._step_fn
            robot = robots[i]
            start = clock()
            try:
                output = step(robot)
            except Exception as exc:  # user code: contain everything it raises
                times.append(clock() - start)
                failures.append(failure_from_exception(i, now, exc))
                continue
            except StepTimeout as stop:  # past the wall limit: say whose call it was
                blame(stop, i, "step()")
                raise
            times.append(clock() - start)
            # two finite numbers, checked inline: this runs once per robot and step
            try:
                speed, heading = output
                if speed.__class__ not in _PLAIN or heading.__class__ not in _PLAIN:
                    _refuse_text_and_truth(speed, heading)  # rare: float() would take them
                speed, heading = float(speed), float(heading)
            except (TypeError, ValueError):
                failures.append(_not_two_numbers(i, now, output, step))
                continue
            if isfinite(speed) and isfinite(heading):
                done.append(i)
                speeds.append(speed)
                headings.append(heading)
            else:
                failures.append(_not_finite(i, now, speed, heading, step, output))
        state.user_time[ids] = times
        if len(done) == state.n:  # every robot, in order: whole columns
            state.reference[:, 0] = speeds
            state.reference[:, 1] = headings
        elif done:
            state.reference[done, 0] = speeds
            state.reference[done, 1] = headings
        return failures


class TeamController(Controller):
    """Calls ``team_step(team)`` once per step with arrays for all active robots."""

    is_team = True

    def __init__(self, name: str, team_step: Any = None, reset: Any = None,
                 factory: type | None = None) -> None:
        self.name = name
        self._team_step = team_step
        self._reset_fn = reset
        self._factory = factory
        self._instance: Any = None

    def reset(self, sim: SimulationParts) -> list[UserFailure]:
        ids = np.flatnonzero(sim.state.active)
        try:
            self._instance = self._factory() if self._factory is not None else None
            hook = getattr(self._instance, "reset", None) if self._instance else self._reset_fn
            if hook is not None:
                hook(Team(sim, ids))
        except Exception as exc:  # user code: contain everything it raises
            return [failure_from_exception(-1, sim.state.time, exc)]
        except StepTimeout as stop:
            blame(stop, -1, "team_reset()")
            raise
        return []

    def compute(self, sim: SimulationParts, ids: np.ndarray) -> list[UserFailure]:
        state = sim.state
        now = state.time
        step = self._instance.team_step if self._instance is not None else self._team_step
        start = time.perf_counter()
        try:
            output = step(Team(sim, ids))
        except Exception as exc:  # user code: contain everything it raises
            state.user_time[ids] = (time.perf_counter() - start) / max(len(ids), 1)
            return [failure_from_exception(-1, now, exc)]
        except StepTimeout as stop:
            blame(stop, -1, "team_step()")
            raise
        state.user_time[ids] = (time.perf_counter() - start) / max(len(ids), 1)
        try:
            speed, heading = output
            speed = _as_rows(speed, ids.shape)
            heading = _as_rows(heading, ids.shape)
        except (TypeError, ValueError):
            return [invalid_output(-1, now, f"team_step() must return (speed_refs, "
                                            f"heading_refs), two arrays of length {len(ids)}; "
                                            f"got {_shown(output)}", step, output)]
        good = np.isfinite(speed) & np.isfinite(heading)
        if np.count_nonzero(good) == len(ids):  # the usual case: no masking needed
            rows = slice(None) if len(ids) == state.n else ids
            state.reference[rows, 0] = speed
            state.reference[rows, 1] = heading
            return []
        state.reference[ids[good], 0] = speed[good]
        state.reference[ids[good], 1] = heading[good]
        where, line = where_of(return_lines(step, output))
        return [UserFailure(int(i), now, "InvalidOutput", f"robot {int(i)}: team_step() returned "
                            f"a non-finite reference (speed_ref={s}, heading_ref={h})", "",
                            where, line)
                for i, s, h in zip(ids[~good], speed[~good], heading[~good], strict=True)]


def _as_rows(values: Any, shape: tuple[int, ...]) -> np.ndarray:
    """A team's output as float rows of ``shape`` (broadcast when it is a scalar or short)."""
    values = np.asarray(values)
    if values.dtype.kind not in ("f", "i", "u"):  # texts and truth values are bugs, not speeds
        raise TypeError(f"not numbers: an array of {values.dtype}")
    values = values.astype(np.float64, copy=False)
    if values.shape == shape:  # the usual case: skip broadcast_to's Python overhead
        return values
    return np.broadcast_to(values, shape)


def controller_from(algorithm: Any, name: str | None = None) -> Controller:
    """Wrap a module, function, class or instance following the contract above."""
    if isinstance(algorithm, Controller):
        return algorithm
    label = name or getattr(algorithm, "__name__", type(algorithm).__name__)
    if isinstance(algorithm, ModuleType):
        found = _from_namespace(vars(algorithm), label)
        if found is None:
            raise AlgorithmError(f"algorithm {label!r}: define step(robot), team_step(team), or a "
                                 "class with a step or team_step method")
        return found
    if inspect.isclass(algorithm):
        if hasattr(algorithm, "team_step"):
            return TeamController(label, factory=algorithm)
        if hasattr(algorithm, "step"):
            return PerRobotController(label, factory=algorithm)
        raise AlgorithmError(f"algorithm class {label!r} has neither step nor team_step")
    if callable(algorithm):
        if getattr(algorithm, "__name__", "") == "team_step":  # named as in a module
            return TeamController(label, team_step=algorithm)
        return PerRobotController(label, step=algorithm)
    raise AlgorithmError(f"algorithm {label!r}: expected a function, class or module, "
                         f"got {type(algorithm).__name__}")


def _from_namespace(namespace: dict[str, Any], name: str) -> Controller | None:
    """Find the algorithm in a module's namespace (``step`` first, then classes)."""
    if callable(namespace.get("team_step")):
        return TeamController(name, team_step=namespace["team_step"],
                              reset=namespace.get("team_reset"))
    if callable(namespace.get("step")):
        return PerRobotController(name, step=namespace["step"], reset=namespace.get("reset"))
    module_name = namespace.get("__name__")
    for value in namespace.values():
        if (inspect.isclass(value) and getattr(value, "__module__", None) == module_name
                and (hasattr(value, "step") or hasattr(value, "team_step"))):
            return controller_from(value, name)
    return None
