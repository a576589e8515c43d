"""Finding algorithms and scenarios by name or by path.

Built-in algorithms live in ``mimics/algorithms/`` and built-in scenarios in
``mimics/scenarios/``, one module each, the module name being the name. A user
passes a path instead: a ``.py`` file (an algorithm, or a scenario defining
``scenario(**params)``), a ``.c``/``.cpp`` algorithm (compiled on first use, see
:mod:`mimics.native`) or a declarative ``.toml`` scenario.

An algorithm may also be ``SCHEME:COMMAND``, a kind of algorithm that an
installed part provides: ``ros:go_to_goal_node.py --robots {robots}`` is a
ROS controller node (:mod:`mimics.interfaces.ros.node_algorithm`). Schemes are
the entry points of the group ``mimics.algorithm_schemes``, found at first
use, so that this module and the batteries never import the parts that provide
them. A scheme object has ``name``, ``resolve(command, base)`` (the command
with its paths made absolute), ``label(command)`` and ``algorithm(command)``
(the display name and a fresh controller).

>>> sorted(name for name, _ in list_algorithms())[:2]
['deployment', 'deployment_team']
"""

from __future__ import annotations

import functools
import hashlib
import importlib
import importlib.util
import inspect
import pkgutil
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

import mimics.algorithms
import mimics.scenarios
from mimics.native import NATIVE_SUFFIXES
from mimics.world.errors import AlgorithmError, MimicsError, ScenarioError
from mimics.world.scenario import Scenario


@functools.cache  # the installed package does not change while it runs (0.6 ms a call)
def _builtin_names(package: ModuleType) -> tuple[str, ...]:
    return tuple(sorted(m.name for m in pkgutil.iter_modules(package.__path__)
                        if not m.name.startswith("_")))


def _first_line(module: ModuleType) -> str:
    return (module.__doc__ or "").strip().splitlines()[0] if module.__doc__ else ""


def _load_file(path: Path, kind: str, limit: float | None = None) -> ModuleType:
    """Import a user's ``.py`` file under a unique module name.

    ``limit`` (s): the import is stopped past it (an endless loop at file level) as a
    step past a run's wall limit is (:mod:`mimics.engine.user_code.watchdog`). Whatever the
    file does at import (a syntax error, an exception, ``sys.exit``, a time-out) is
    one :class:`MimicsError` naming the file and its line.
    """
    if not path.is_file():
        raise MimicsError(f"{kind} file {path} does not exist")
    digest = hashlib.sha1(str(path.resolve()).encode()).hexdigest()[:10]
    name = f"mimics_user_{kind}_{path.stem}_{digest}"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    if spec is None or spec.loader is None:
        raise MimicsError(f"{path}: cannot be imported as Python")
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    from mimics.engine.user_code import LoadTimeout, StepTimeout, watched_load

    try:
        with watched_load(limit):
            spec.loader.exec_module(module)
    except SyntaxError as exc:
        del sys.modules[name]
        raise MimicsError(f"{path}, line {exc.lineno}: syntax error: {exc.msg}") from exc
    except StepTimeout as exc:  # an endless loop at file level, stopped by the watchdog
        del sys.modules[name]
        raise LoadTimeout(f"{path}{_line_in(exc, path)}: importing it did not finish within "
                          f"{limit:g} s (an endless loop outside step()?)") from None
    except (Exception, SystemExit) as exc:  # user code at import time: report it in one line
        del sys.modules[name]
        from mimics.engine.user_code import first_line

        what = (f"called sys.exit({exc.code!r})" if isinstance(exc, SystemExit)
                else f"raised {type(exc).__name__}: {first_line(exc)}")
        raise MimicsError(f"{path}{_line_in(exc, path)}: importing it {what}") from exc
    return module


def _line_in(exc: BaseException, path: Path) -> str:
    """``", line 7"``: the user's line that ``exc`` came from (``" (at other.py:3)"`` when
    it is in another file of the user's; "" when none is)."""
    from mimics.engine.user_code import failure_place

    place = failure_place(exc)
    if place is None:
        return ""
    if Path(place.file).resolve() == path.resolve():
        return f", line {place.line}"
    return f" (at {place})"


def _looks_like_path(name: str) -> bool:
    return name.endswith((".py", ".toml", *NATIVE_SUFFIXES)) or "/" in name or "\\" in name


# -- algorithms --------------------------------------------------------------

def list_algorithms() -> list[tuple[str, str]]:
    """Built-in algorithms as ``(name, one-line description)``."""
    return [(name, _first_line(importlib.import_module(f"mimics.algorithms.{name}")))
            for name in _builtin_names(mimics.algorithms)]


SCHEME_GROUP = "mimics.algorithm_schemes"


def algorithm_scheme(text: str) -> tuple[Any, str] | None:
    """The scheme object and command of a ``SCHEME:COMMAND`` algorithm, else None.

    Raises:
        AlgorithmError: ``SCHEME:`` looks like a scheme that no installed part provides.
    """
    name, colon, command = text.partition(":")
    if not colon or len(name) < 2 or not name.isidentifier():  # "C:\\..." is a path
        return None
    providers = _scheme_providers()
    if name not in providers:
        known = ", ".join(f"{n}:" for n in sorted(providers)) or "none installed"
        raise AlgorithmError(f"algorithm {text!r}: unknown kind {name + ':'!r} (known: {known}; "
                             "is mimics installed with pip?)")
    return providers[name].load(), command.strip()


@functools.cache  # installed parts do not change while mimics runs; a scan takes ms
def _scheme_providers() -> dict[str, Any]:
    import importlib.metadata  # lazily: 20 ms, and only algorithms with a scheme need it

    return {point.name: point for point in importlib.metadata.entry_points(group=SCHEME_GROUP)}


def find_algorithm(name_or_path: str | Path, *, load_limit: float | None = None
                   ) -> tuple[str, Any]:
    """The algorithm's display name and module, from a built-in name, a file path or a scheme.

    ``load_limit`` (s): a ``.py`` file's import is stopped past it (see ``_load_file``).

    A C or C++ file gives a ready controller instead of a module (compiled on
    first use, then found in the cache): a fresh one per call; so does a
    ``SCHEME:COMMAND`` algorithm.
    """
    text = str(name_or_path)
    scheme = algorithm_scheme(text)
    if scheme is not None:
        provider, command = scheme
        return provider.algorithm(command)  # type: ignore[no-any-return]
    if _looks_like_path(text):
        path = Path(text)
        if path.suffix.lower() in NATIVE_SUFFIXES:
            from mimics.native.adapter import native_controller

            return path.name, native_controller(path)
        if path.suffix != ".py":
            raise AlgorithmError(f"algorithm {text!r}: expected a .py, .c or .cpp file or a "
                                 "built-in name")
        return path.stem, _load_file(path, "algorithm", load_limit)
    if text not in _builtin_names(mimics.algorithms):
        known = ", ".join(_builtin_names(mimics.algorithms))
        raise AlgorithmError(f"unknown algorithm {text!r} (expected a .py, .c or .cpp file or "
                             f"one of: {known})")
    return text, importlib.import_module(f"mimics.algorithms.{text}")


# -- scenarios ---------------------------------------------------------------

def list_scenarios() -> list[tuple[str, str]]:
    """Built-in scenarios as ``(name, one-line description)``."""
    return [(name, _first_line(importlib.import_module(f"mimics.scenarios.{name}")))
            for name in _builtin_names(mimics.scenarios)]


def scenario_seed_changes(name: str) -> str:
    """What the run's seed changes in a built-in scenario (its ``SEED_CHANGES``), besides
    the sensors' noise."""
    module = importlib.import_module(f"mimics.scenarios.{name}")
    return str(getattr(module, "SEED_CHANGES", "nothing in the layout"))


#: Settings of the stall rules that every scenario takes as a parameter (issue 54: the
#: deadlock rule is set per battery or per run, whatever the scenario), and of what a
#: collision does (``on_collision``: deactivate, or stall as Stage's robots do).
STALL_SETTINGS = ("deadlock_distance", "deadlock_window", "deactivate_on_deadlock",
                  "livelock_window", "livelock_progress", "on_collision")


def scenario_parameters(name_or_path: str | Path) -> dict[str, Any]:
    """The keyword parameters a scenario accepts, with their defaults."""
    factory, _ = _scenario_factory(str(name_or_path))
    if factory is None:
        return {}
    from mimics.world.scenario import Settings

    own = {p.name: p.default for p in inspect.signature(factory).parameters.values()
           if p.default is not inspect.Parameter.empty}
    stall = {name: getattr(Settings(), name) for name in STALL_SETTINGS if name not in own}
    return {**own, **stall, "noise": "on"}


def _scenario_factory(text: str) -> tuple[Any, str]:
    if text.endswith(".toml"):
        return None, Path(text).stem
    if _looks_like_path(text):
        module = _load_file(Path(text), "scenario")
        label = Path(text).stem
    elif text in _builtin_names(mimics.scenarios):
        module = importlib.import_module(f"mimics.scenarios.{text}")
        label = text
    else:
        known = ", ".join(_builtin_names(mimics.scenarios))
        raise ScenarioError(f"unknown scenario {text!r} (expected a .py or .toml file or one "
                            f"of: {known})")
    factory = getattr(module, "scenario", None)
    if not callable(factory):
        raise ScenarioError(f"scenario {text!r}: define a function scenario(**params) that "
                            "returns a Scenario")
    return factory, label


def load_scenario(name_or_path: str | Path, *, allow_overlap: bool = False,
                  run_seed: int | None = None, **params: Any) -> Scenario:
    """Build a scenario from a built-in name, a ``.py`` file or a ``.toml`` file.

    ``params`` are the scenario's keyword parameters (``robots=60``); unknown
    ones are errors naming the parameter and the ones that exist, and so are
    NaN or infinite values and robot counts past the limit. The start state is
    checked (``mimics.world.start_state.validate_scenario``) unless
    ``allow_overlap`` (or the scenario's ``settings.allow_overlap``) keeps
    robots that start touching walls or each other.

    ``run_seed``, the run's seed, reaches the scenario's own randomness: a
    scenario whose ``scenario()`` takes ``seed`` is built with it (and a TOML
    file's random generators draw from it), unless ``seed`` is among ``params``
    (a fixed layout). ``noise = "on"`` or ``"off"`` is accepted by every
    scenario (``settings.noise``).
    """
    from mimics.world.limits import MAX_ROBOTS, MAX_SEED, check_finite, check_whole
    from mimics.world.start_state import validate_scenario

    text = str(name_or_path)
    for key, value in params.items():
        check_finite(f"scenario parameter {key}", value)
    if "robots" in params:
        check_whole("scenario parameter robots", params["robots"], 1, MAX_ROBOTS)
    if "seed" in params:
        check_whole("scenario parameter seed", params["seed"], 0, MAX_SEED)
    if text.endswith(".toml"):
        from mimics.world.scenario_files import load_scenario_toml

        if allow_overlap:
            params = {**params, "allow_overlap": True}
        return load_scenario_toml(text, run_seed=run_seed, **params)
    noise = params.pop("noise", None)
    if noise is not None and noise not in ("on", "off"):
        raise ScenarioError(f"scenario parameter noise: expected on or off, got {noise!r}")
    factory, label = _scenario_factory(text)
    accepted = inspect.signature(factory).parameters
    takes_any = any(p.kind is inspect.Parameter.VAR_KEYWORD for p in accepted.values())
    stall = {key: params.pop(key) for key in STALL_SETTINGS
             if key in params and key not in accepted}  # a scenario's own parameter wins
    for key in params:
        if key not in accepted and not takes_any:
            raise ScenarioError(f"scenario {label!r} has no parameter {key!r} (expected one of: "
                                f"{', '.join(accepted) or 'none'})")
    given = dict(params)  # what the user chose, recorded as the scenario's parameters
    if run_seed is not None and "seed" not in params and ("seed" in accepted or takes_any):
        params = {**params, "seed": run_seed}
    try:
        built = factory(**params)
    except MimicsError:
        raise
    except (TypeError, ValueError) as exc:
        raise ScenarioError(f"scenario {label!r}: {exc}") from exc
    except Exception as exc:  # the user's code (or NumPy's MemoryError in it): one line
        raise ScenarioError(f"scenario {label!r}: scenario() raised {type(exc).__name__}: "
                            f"{exc}") from exc
    if not isinstance(built, Scenario):
        raise ScenarioError(f"scenario {label!r}: scenario() returned {type(built).__name__}, "
                            "expected a Scenario")
    defaults = {k: p.default for k, p in accepted.items()
                if p.default is not inspect.Parameter.empty
                and not (k == "seed" and "seed" not in given and run_seed is not None)}
    if noise is not None:
        built = built.with_settings(noise=noise)
        given["noise"] = noise
    if stall:
        built = built.with_settings(**stall)  # Settings checks the values, naming the key
        given.update(stall)
    named = _named(built, label, {**defaults, **given})
    validate_scenario(named, f"scenario {label!r}",
                      allow_overlap=allow_overlap or named.settings.allow_overlap)
    return named


def _named(scenario: Scenario, label: str, params: dict[str, Any]) -> Scenario:
    from dataclasses import replace

    return replace(scenario, name=label, parameters=params)
