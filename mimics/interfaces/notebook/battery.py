"""BatteryView: a battery's runs, report and plots, in a notebook or a script.

``mimics.run_battery(spec_or_path, workers=...)`` runs a battery with the
battery driver (:func:`mimics.batteries.driver.run_battery`: the same worker
processes, database and folder as ``mimics battery run``), showing its progress
bar in the cell (Rich's Jupyter display), and returns a :class:`BatteryView`;
``mimics.load_battery(folder)`` opens one already run (or still running).
``.table`` is one row per run, ``.summary()`` the report's aggregate (means and
95% intervals per algorithm x scenario), ``.intervals()`` and ``.compare()`` the
report's per-cell intervals and paired comparison (``mimics battery compare``),
``.warnings`` its identical-seed warnings, ``.plot(...)`` the figures of
``mimics battery plot``, ``.arrivals()`` the arrival curves (the fraction of
goal robots arrived against time) as a table, ``.run(id)`` one run as a
:class:`~mimics.interfaces.notebook.run.RunView`.

Everything taken from the battery report (:mod:`mimics.batteries.report`) goes
through :meth:`BatteryView.report_tables`, one place.
"""

from __future__ import annotations

import html
import time
from pathlib import Path
from typing import Any

import pandas as pd

from mimics.interfaces.notebook.columns import COMPARE, SUMMARY, chosen, interval_columns
from mimics.interfaces.notebook.html import enable_figure_display, figure_img, in_kernel
from mimics.world.errors import MimicsError

#: The figures of ``mimics battery plot``, by the name ``plot(kind)`` takes.
PLOTS = ("outcomes", "time_to_goal", "arrivals", "wall_time_vs_robots")
#: The columns of :meth:`BatteryView.arrivals`.
ARRIVAL_COLUMNS = ("algorithm", "scenario", "parameters", "time", "fraction", "low", "high",
                   "runs", "robots", "arrived", "horizon")


class BatteryView:
    """A battery folder: its runs, report and figures (read afresh at each use).

    Args:
        folder: the battery folder (with its ``battery.db``).
        result: what the session that ran it left (counts, time), if it ran here.
    """

    def __init__(self, folder: str | Path, result: Any = None) -> None:
        self.folder = Path(folder)
        self.result = result

    @classmethod
    def open(cls, folder: str | Path) -> BatteryView:
        """A battery folder, checked.

        Raises:
            MimicsError: when ``folder`` is not a battery folder.
        """
        from mimics.batteries.store import BatteryStore

        BatteryStore.open(folder).close()  # a one-line error for anything else
        return cls(folder)

    def __repr__(self) -> str:
        counts = ", ".join(f"{n} {state}" for state, n in self.counts.items())
        return f"BatteryView({str(self.folder)!r}: {counts or 'no runs'})"

    # -- the battery report ----------------------------------------------------------

    def evidence(self, baseline: str | None = None, metrics: list[str] | None = None, *,
                 exclude_failed: bool = False, adjust: str = "holm", method: str = "t"
                 ) -> Any:
        """Everything ``mimics battery report`` reads from the battery
        (:class:`mimics.batteries.evidence.Evidence`): intervals, comparison, costs,
        failed runs, cells a stopping rule left short of their target, warnings.

        Raises:
            MimicsError: an unknown baseline, metric, adjustment or method.
        """
        from mimics.batteries.evidence import battery_evidence

        return battery_evidence(self.folder, baseline=baseline, metrics=metrics,
                                exclude_failed=exclude_failed, adjust=adjust, method=method)

    def report_tables(self) -> dict[str, pd.DataFrame]:
        """The battery report's tables, by name, as ``mimics battery report`` shows them.

        ``runs``: one row per run; ``failures``: the failed runs; ``aggregate``: per
        algorithm x scenario (x parameters), runs by outcome and each count's mean
        with its 95% interval over the done runs; ``intervals``: each metric's
        estimate and 95% interval per cell (t for means, Wilson for proportions;
        failed runs count as success 0); ``comparison``: each algorithm against the
        first, paired by seed, p-values Holm-adjusted; ``costs``: wall and user-code
        time per cell.
        """
        from mimics.batteries.report import aggregate
        from mimics.batteries.tasks import FAILED_STATES

        found = self.evidence()
        runs = found.table
        if runs.empty:
            return {"runs": runs, "failures": runs, "aggregate": pd.DataFrame(),
                    "intervals": pd.DataFrame(), "comparison": pd.DataFrame(),
                    "costs": pd.DataFrame()}
        return {"runs": runs,
                "failures": runs[runs["state"].isin(FAILED_STATES)].reset_index(drop=True),
                "aggregate": aggregate(runs), "intervals": found.intervals,
                "comparison": found.comparison, "costs": found.costs}

    @property
    def table(self) -> pd.DataFrame:
        """One row per run (the columns of ``mimics battery report --csv``, and more)."""
        from mimics.batteries.report import runs_table

        return runs_table(self.folder)

    def summary(self, columns: str | list[str] | None = None) -> pd.DataFrame:
        """The report's aggregate: one row per algorithm x scenario (x parameter point).

        Args:
            columns: None: the runs, the failed ones, and the mean goals reached and
                collisions with their 95% half-widths; ``"all"``: every count (done,
                unfinished, deadlocks, escapes, wall time...); or a list of names.
        """
        return chosen(self.report_tables()["aggregate"], columns, SUMMARY, "summary")

    def intervals(self, metrics: list[str] | None = None, *, exclude_failed: bool = False,
                  method: str = "t", columns: str | list[str] | None = None
                  ) -> pd.DataFrame:
        """Per cell, its runs, done and failed, and each metric's estimate with its 95%
        interval and the runs it rests on (the intervals table of ``mimics battery
        report``).

        Args:
            columns: None: the runs, the failed ones and the estimate and bounds of
                ``metrics`` (default: success and time to goal); ``"all"``: every
                metric with the runs it rests on; or a list of names.
        """
        table = self.evidence(metrics=metrics, exclude_failed=exclude_failed,
                              method=method).intervals
        return chosen(table, columns, interval_columns(table, metrics), "intervals")

    def compare(self, baseline: str | None = None, metrics: list[str] | None = None, *,
                exclude_failed: bool = False, adjust: str = "holm", method: str = "t",
                columns: str | list[str] | None = None) -> pd.DataFrame:
        """Each algorithm minus ``baseline`` (default: the battery's first), paired by
        scenario, parameters and seed (``mimics battery compare``): rates by Newcombe's
        interval and McNemar's test, means by the t interval and Wilcoxon's test, raw
        and adjusted p-values, the pairs, the primary metric marked.

        ``columns``: None: the difference, its interval and the adjusted p-value;
        ``"all"``: the test, the raw p-value, the primary mark and notes too; or a list.

        Raises:
            MimicsError: an unknown baseline, metric, adjustment, method or column.
        """
        table = self.evidence(baseline, metrics, exclude_failed=exclude_failed, adjust=adjust,
                              method=method).comparison
        return chosen(table, columns, COMPARE, "compare")

    @property
    def failed(self) -> list[str]:
        """One line per cell with failed runs: how many, their states and seeds."""
        return self.evidence().failed

    @property
    def unmet(self) -> list[str]:
        """Cells that a stopping rule stopped at ``max_seeds`` short of its target."""
        return self.evidence().unmet

    @property
    def warnings(self) -> list[str]:
        """One line per cell whose seeds gave identical runs, with what made them so."""
        return self.evidence().warnings

    @property
    def counts(self) -> dict[str, int]:
        """Runs by state (done, error, timeout, crashed, pending...)."""
        runs = self.table
        if runs.empty:
            return {}
        return {str(k): int(v) for k, v in runs["state"].value_counts().items()}

    def run(self, run_id: int) -> Any:
        """Run ``run_id`` of the table (its ``id`` column) as a RunView.

        Raises:
            MimicsError: no such run, or one without a folder yet.
        """
        from mimics.interfaces.notebook.run import RunView
        from mimics.records.run_folder import load_run

        runs = self.table
        chosen = runs[runs["id"] == run_id] if not runs.empty else runs
        if chosen.empty:
            raise MimicsError(f"{self.folder}: no run #{run_id} in this battery")
        folder = Path(chosen["folder"].iloc[0])
        if not folder.is_dir():
            raise MimicsError(f"{self.folder}: run #{run_id} has no folder yet "
                              f"(state {chosen['state'].iloc[0]})")
        return RunView(load_run(folder))

    # -- figures ---------------------------------------------------------------------

    def plot(self, kind: str = "outcomes", *, width_px: int | None = None,
             height_px: int | None = None, **options: Any) -> Any:
        """A figure of ``mimics battery plot`` (a Matplotlib Figure).

        Args:
            kind: ``"outcomes"`` (robot outcomes and run statuses), ``"time_to_goal"``
                (one point per run: its restricted mean time to goal, a panel per
                parameter point), ``"arrivals"`` (the arrival curves, see
                ``arrivals()``) or ``"wall_time_vs_robots"`` (the paper's Figure 2,
                from the runs of the ``line`` scenario; ``scenario=`` names another).
            width_px: width in pixels (the plot's own default otherwise).
            height_px: height in pixels (the plot's own default otherwise).

        Raises:
            MimicsError: an unknown kind, or a battery with nothing to plot.
        """
        from mimics.interfaces import plots

        if kind not in PLOTS:
            raise MimicsError(f"plot: expected one of {', '.join(PLOTS)}, got {kind!r}")
        size = {k: v for k, v in (("width_px", width_px), ("height_px", height_px))
                if v is not None}
        enable_figure_display()
        table = plots.battery_table(self.folder)
        return getattr(plots, f"plot_{kind}")(table, None, **size, **options)

    def arrivals(self) -> pd.DataFrame:
        """The arrival curves as a tidy table: per algorithm x scenario x parameter point,
        the Kaplan-Meier fraction of goal robots arrived by each ``time`` (s) with its
        pointwise 95% interval ``low``-``high`` (NaN where undefined), over every goal
        robot of the cell's done runs, each robot that never arrived censored at its run's
        horizon (:func:`mimics.batteries.arrivals.arrival_curves`); the fraction is 0
        before the first time. ``runs``, ``robots``, ``arrived`` and ``horizon`` are the
        cell's. Runs of batteries recorded before mimics kept arrival times have no curve.
        """
        from mimics.batteries.arrivals import arrival_curves

        runs = self.table
        frames = [pd.DataFrame({
            "algorithm": algorithm, "scenario": scenario, "parameters": point,
            "time": curve.times, "fraction": curve.fraction, "low": curve.low,
            "high": curve.high, "runs": curve.runs, "robots": curve.robots,
            "arrived": curve.arrived, "horizon": curve.horizon})
            for (algorithm, scenario, point), curve in
            (arrival_curves(runs) if not runs.empty else {}).items() if curve.times.size]
        if not frames:
            return pd.DataFrame(columns=list(ARRIVAL_COLUMNS))
        return pd.concat(frames, ignore_index=True)[list(ARRIVAL_COLUMNS)]

    def _repr_html_(self) -> str:
        tables = self.report_tables()
        runs, failures = tables["runs"], tables["failures"]
        # the default columns, as summary(), intervals() and compare() give them
        agg = chosen(tables["aggregate"], None, SUMMARY, "summary")
        intervals = chosen(tables["intervals"], None,
                           interval_columns(tables["intervals"], None), "intervals")
        comparison = chosen(tables["comparison"], None, COMPARE, "compare")
        counts = ", ".join(f"{n} {state}" for state, n in self.counts.items()) or "no runs"
        parts = [f'<div class="mimics-battery"><h4>{html.escape(str(self.folder))}: '
                 f"{len(runs)} runs ({html.escape(counts)})</h4>"]
        if not agg.empty:
            parts.append("<p>Per algorithm x scenario: mean and 95% interval over the done "
                         "runs</p>")
            parts.append(agg.to_html(index=False, float_format=lambda v: f"{v:.3g}",
                                     na_rep="-"))
        for title, frame in (("Per cell: each metric with its 95% interval (t for means, "
                              "Wilson for proportions)", intervals),
                             ("Paired by seed against the baseline: mean difference, 95% "
                              "t interval, Wilcoxon signed-rank p", comparison)):
            if not frame.empty:
                parts.append(f"<p>{title}</p>")
                parts.append(frame.to_html(index=False, float_format=lambda v: f"{v:.3g}",
                                           na_rep="-"))
        parts.extend(f"<p>warning: {html.escape(line)}</p>" for line in self.warnings)
        if not failures.empty:
            parts.append(f"<p>{len(failures)} failed run(s)</p>")
            parts.append(failures[["id", "algorithm", "scenario", "seed", "state", "error"]]
                         .to_html(index=False))
        try:
            parts.append(figure_img(self.plot("outcomes"), "outcomes"))
        except MimicsError as exc:  # no run has finished yet
            parts.append(f"<p>{html.escape(str(exc))}</p>")
        parts.append("</div>")
        return "".join(parts)


def run_battery(spec: Any, out: str | Path | None = None, *, workers: int | None = None,
                dask: str | None = None, progress: bool | None = None) -> BatteryView:
    """Run a battery with the battery driver and return its view.

    Args:
        spec: a battery file, a dict in its form (``{"battery": {...}, "scenarios":
            [...]}``), or a ``mimics.batteries.spec.BatterySpec``. In a dict, the
            algorithms may be functions or classes (defined in the notebook: they are
            pickled to the workers) as well as names and paths.
        out: the battery folder (default: ``batteries/NAME-TIME`` in the current
            folder, NAME being the file's stem or ``battery``). A folder holding this
            same battery is continued (its runs not yet done run; a finished one is
            just opened), one holding another battery is refused.
        workers: local worker processes (default: one per core).
        dask: a Dask scheduler address instead of local workers.
        progress: show the progress bar (default: in a notebook cell, or on a terminal;
            False: none).

    Raises:
        MimicsError: a bad battery, or a folder that holds another battery; nothing runs.
    """
    from mimics.batteries.driver import resume_battery
    from mimics.batteries.driver import run_battery as drive
    from mimics.batteries.spec import BatterySpec, load_battery, spec_from_dict
    from mimics.interfaces.notebook.battery_spec import same_battery, with_inline_algorithms
    from mimics.world.limits import check_time, check_wall_seconds, check_whole
    from mimics.world.output_paths import as_path, check_outputs

    # the arguments first, each named: nothing is created for a bad one
    if workers is not None:
        check_whole("run_battery: workers", workers, 1, 4096)
    if dask is not None and not (isinstance(dask, str) and dask.strip()):
        raise MimicsError(f"run_battery: dask: expected a scheduler address (a str), got "
                          f"{dask!r}")
    if progress is not None and not isinstance(progress, bool):
        raise MimicsError(f"run_battery: progress: expected True, False or None, got "
                          f"{progress!r}")
    if out is not None:
        out = as_path("run_battery: out", out)
    if isinstance(spec, dict):
        spec = spec_from_dict(with_inline_algorithms(spec), base=Path.cwd(), source="")
    elif not isinstance(spec, BatterySpec):
        if not isinstance(spec, str | Path):
            raise MimicsError(f"run_battery: expected a battery file, a dict or a BatterySpec, "
                              f"got {type(spec).__name__}")
        spec = load_battery(spec)
    else:  # built by hand: its numbers were not read through a battery file's checks
        if spec.time is not None:
            check_time("run_battery: spec.time", spec.time)
        check_wall_seconds("run_battery: spec.timeout", spec.timeout)
    check_outputs({"run_battery: out": out}, {"the battery file": spec.source or None})
    if out is None:
        stem = Path(spec.source).stem if spec.source else "battery"
        out = Path("batteries") / f"{stem}-{time.strftime('%Y%m%d-%H%M%S')}"
    again = same_battery(out, spec)  # a cell run again: go on with its battery

    def run(bar: bool | None) -> Any:
        if again:
            return resume_battery(out, workers=workers, dask=dask, progress=bar)
        return drive(spec, out, workers=workers, dask=dask, progress=bar)

    if (progress is None or progress) and in_kernel():
        with CellProgress(out, total=len(spec.runs())):
            result = run(False)
    else:
        result = run(progress)
    return BatteryView(out, result)


class CellProgress:
    """A progress bar in the notebook cell (``tqdm.auto``) while a battery runs.

    The bar is shown from the kernel's main thread (so that it lands in the
    cell) and moved by a thread that reads the battery's database every
    ``period`` seconds (:func:`mimics.batteries.status.battery_status`, safe
    while the battery runs): runs finished out of all, and the failures.

    Args:
        folder: the battery folder being run.
        total: runs in the battery.
        period: seconds between two readings.
    """

    def __init__(self, folder: str | Path, total: int, period: float = 0.5) -> None:
        import threading

        from tqdm.auto import tqdm

        self.folder = Path(folder)
        self.bar = tqdm(total=total, desc="battery", unit="run", dynamic_ncols=True)
        self.period = period
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._follow, name="mimics-battery-bar",
                                        daemon=True)

    def __enter__(self) -> CellProgress:
        self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._stop.set()
        self._thread.join(5.0)
        self.update()
        self.bar.close()

    def _follow(self) -> None:
        while not self._stop.wait(self.period):
            self.update()

    def update(self) -> None:
        """Move the bar to the runs finished now (nothing before the database exists)."""
        from mimics.batteries.status import battery_status
        from mimics.batteries.tasks import FAILED_STATES

        if not (self.folder / "battery.db").is_file():
            return
        try:
            status = battery_status(self.folder, max_errors=0)
        except Exception:  # a database being created or locked: the next reading will do
            return
        failed = sum(status.counts.get(state, 0) for state in FAILED_STATES)
        self.bar.n = status.total - status.left
        self.bar.set_postfix(failed=failed, refresh=False)
        self.bar.refresh()
