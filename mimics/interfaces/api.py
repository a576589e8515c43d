"""The Python entry points: one simulation, a run folder, a battery, a live view.

``simulate`` and ``load_run`` give a :class:`~mimics.interfaces.notebook.run.RunView`
(tables, summary, plot, replay; shown in a notebook cell), ``run_battery`` and
``load_battery`` a :class:`~mimics.interfaces.notebook.battery.BatteryView`,
``show`` a live view in a notebook cell.

>>> import mimics
>>> run = mimics.simulate("line", "go_to_goal", robots=3, time=21.8, seed=1,
...                       params={"random_yaw": False})  # facing their goals
>>> run.status, run.reached_goal
('completed', 3)
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from mimics.engine.simulation import Policy
from mimics.interfaces.notebook.run import RunView, record_run
from mimics.interfaces.user_errors import user_code_error
from mimics.records.layout import check_run_output
from mimics.records.run_folder import load_run as load_run_folder
from mimics.records.runner import prepare
from mimics.world.errors import MimicsError
from mimics.world.output_paths import as_path
from mimics.world.scenario import Scenario

if TYPE_CHECKING:
    from mimics.interfaces.notebook.animation import Animation
    from mimics.interfaces.notebook.battery import BatteryView
    from mimics.interfaces.notebook.widget import LiveWidget


def simulate(scenario: str | Path | Scenario, algorithm: Any, *, robots: int | None = None,
             time: float | None = None, seed: int = 0, policy: Policy = "abort",
             out: str | Path | None = None, wall_limit: float | None = None,
             params: dict[str, Any] | None = None,
             observers: tuple[Any, ...] = (), record_scans: bool = False,
             allow_overlap: bool = False,
             on_error: Literal["raise", "record"] = "raise") -> RunView:
    """Run one simulation and return its outcome, recorded; with ``out``, also write its folder.

    Without ``out`` the run is recorded in memory (the same rows a run folder
    holds; nothing is written): ``.trajectory``, ``.events``, ``.summary()``,
    ``.plot()``, ``.animate()``, and ``.save(folder)`` to write it later.

    Args:
        scenario: a built-in name (``"line"``), a ``.py``/``.toml`` file, or a Scenario.
        algorithm: a built-in name, a ``.py`` file, or a module/function/class.
        robots: shorthand for the scenario parameter ``robots``.
        time: simulated seconds (default: the scenario's time limit).
        seed: seeds every random draw; same inputs and seed give identical results.
        policy: ``"abort"`` or ``"deactivate"`` on exceptions in user code.
        out: a folder for the run's records (summary.json and logs).
        wall_limit: stop after this many wall-clock seconds, also inside a step that
            does not return (status ``wall_limit``, ``error`` naming the robot and line).
        params: other scenario parameters.
        observers: extra observers (e.g. a live view).
        record_scans: with ``out``, also record the laser scans (scans.parquet).
        allow_overlap: keep robots that start touching walls or each other, or outside
            the map (by default the scenario is refused, naming them).
        on_error: when the algorithm fails (status ``error``), ``"raise"``
            ``mimics.UserCodeError`` (the recorded run as its
            ``.run``, the algorithm's exception as its cause), or ``"record"``: return the
            run, its ``error`` in the summary.

    Raises:
        UserCodeError: the algorithm failed, with ``on_error="raise"``.
        MimicsError: a bad scenario, algorithm or argument (before anything runs).
    """
    if on_error not in ("raise", "record"):
        raise MimicsError(f"on_error: expected 'raise' or 'record', got {on_error!r}")
    _check_flag("record_scans", record_scans)
    _check_flag("allow_overlap", allow_overlap)
    if out is not None:  # before the run: a folder over one of its inputs is refused
        check_run_output("out", as_path("out", out), {"the scenario file": _input_file(scenario),
                                                      "the algorithm file": _input_file(algorithm)})
    sim = prepare(scenario, algorithm, robots=robots, time=time, seed=seed, policy=policy,
                  wall_limit=wall_limit, params=params, observers=observers,
                  allow_overlap=allow_overlap)
    view = record_run(sim, out, record_scans=record_scans)
    if view.status == "error" and on_error == "raise":
        raise user_code_error(view, sim.user_exception)
    return view


def _check_flag(name: str, value: Any) -> None:
    if not isinstance(value, bool):
        raise MimicsError(f"{name}: expected True or False, got {value!r}")


def _input_file(given: Any) -> Path | None:
    """The file a scenario or algorithm argument names (None: a name or an object)."""
    if isinstance(given, str | Path) and Path(given).is_file():
        return Path(given)
    return None


def load_run(path: str | Path) -> RunView:
    """Open a run folder: the same object as ``simulate`` returns.

    Its files are read when first used (``mimics.records.run_folder.load_run``).

    Raises:
        MimicsError: in one line naming the folder or file, when the folder is
            not a run, or its summary or a Parquet file is unreadable or truncated.
    """
    return RunView(load_run_folder(as_path("load_run: path", path)))


def run_battery(spec: Any, out: str | Path | None = None, *, workers: int | None = None,
                dask: str | None = None, progress: bool | None = None) -> BatteryView:
    """Run a battery (a battery file, a dict of one, or a spec) and return its results.

    See :func:`mimics.interfaces.notebook.battery.run_battery`.
    """
    from mimics.interfaces.notebook.battery import run_battery as run

    return run(spec, out, workers=workers, dask=dask, progress=progress)


def load_battery(path: str | Path) -> BatteryView:
    """Open a battery folder (finished or not): its table, report and plots."""
    from mimics.interfaces.notebook.battery import BatteryView

    return BatteryView.open(path)


def show(scenario: str | Path | Scenario, algorithm: Any, **options: Any
         ) -> LiveWidget | Animation:
    """A live view of a new simulation in a notebook cell (Play/Pause/Step/Stop, speed).

    See :func:`mimics.interfaces.notebook.live.show` for the options.
    """
    import inspect

    from mimics.interfaces.notebook.live import show as live

    known = [name for name, p in inspect.signature(live).parameters.items()
             if p.kind is p.KEYWORD_ONLY]
    unknown = sorted(set(options) - set(known))
    if unknown:
        raise MimicsError(f"show: unknown option {unknown[0]!r} (expected one of: "
                          f"{', '.join(known)})")
    return live(scenario, algorithm, **options)
