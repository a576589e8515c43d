"""The Batteries page's API: set up, start, watch, resume and re-run batteries.

A battery started here is an ordinary battery folder under ``batteries/``,
run by :func:`mimics.batteries.driver.run_battery` in a thread of the server
(its runs go to the driver's own isolated worker processes). Everything the
page shows comes from the battery's SQLite state
(:func:`~mimics.batteries.status.battery_status`,
:func:`~mimics.batteries.report.runs_table`), so it is right after a reload of
the page and after a restart of the server, when the battery can be resumed.
"""

from __future__ import annotations

import json
import os
import re
import tempfile
from pathlib import Path
from typing import Annotated, Any

import tomli_w
from fastapi import APIRouter, HTTPException, Query, Request
from fastapi.responses import Response
from pydantic import Field

from mimics.batteries.driver import lock_holder, rerun_failed, resume_battery, run_battery
from mimics.batteries.spec import POLICIES, spec_from_dict
from mimics.batteries.status import battery_status
from mimics.batteries.store import DB_NAME
from mimics.catalog import list_scenarios
from mimics.interfaces.web.algorithms import algorithm_ref
from mimics.interfaces.web.bodies import StrictBody
from mimics.interfaces.web.security import Workspace

router = APIRouter(prefix="/api/batteries", tags=["batteries"])
_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,63}$")
PLOTS = ("outcomes.png", "time_to_goal.png", "arrivals.png", "wall_time_vs_robots.png")


class ScenarioChoice(StrictBody):
    """A scenario (built-in name or workspace ``.toml``) and its parameters (lists sweep)."""

    name: str
    params: dict[str, Any] = Field(default_factory=dict)


class BatteryBody(StrictBody):
    """A battery: algorithms x scenarios x seeds (x parameter values)."""

    name: str
    algorithms: list[str] = Field(min_length=1, max_length=50)
    scenarios: list[ScenarioChoice] = Field(min_length=1, max_length=50)
    seeds: int | list[int] = 1
    time: float | None = Field(default=None, gt=0)
    timeout: float = Field(default=300.0, gt=0)
    policy: str = "abort"
    until: dict[str, Any] | None = None  # a [battery.until] table (then `seeds` is ignored)
    dry_run: bool = False


class FolderBody(StrictBody):
    """A battery folder of the workspace."""

    path: str


def _scenario_ref(workspace: Workspace, name: str) -> str:
    """A built-in name, or the scenario file's path relative to ``batteries/`` (where the
    battery file is written, and what ``mimics battery run`` resolves it against): the
    file holds no absolute path, so the workspace can be moved or shared."""
    if name in [n for n, _ in list_scenarios()]:
        return name
    real = workspace.resolve(name, must_exist=True)
    if workspace.folder("scenarios") not in real.parents or real.suffix != ".toml":
        raise HTTPException(400, f"scenario {name!r}: expected a built-in or a .toml file "
                                 "under scenarios/")
    return _from_batteries(workspace, real)


def _from_batteries(workspace: Workspace, real: Path) -> str:
    return os.path.relpath(real, workspace.folder("batteries")).replace(os.sep, "/")


def _algorithm_entry(workspace: Workspace, name: str) -> str:
    """A built-in name, or the algorithm file's path relative to ``batteries/``."""
    ref = algorithm_ref(workspace, name)
    return ref if not ref.endswith(".py") else _from_batteries(workspace, Path(ref))


def battery_folder(workspace: Workspace, path: str) -> Path:
    """The real path of a battery folder (holding battery.db) under ``batteries/``."""
    real = workspace.resolve(path, must_exist=True)
    if workspace.folder("batteries") not in real.parents or not (real / DB_NAME).is_file():
        raise HTTPException(400, f"{path}: not a battery folder under batteries/")
    return real


@router.get("")
def list_batteries(request: Request) -> dict[str, Any]:
    """The workspace's battery folders, each with its counts and whether it runs."""
    workspace: Workspace = request.app.state.workspace
    found = []
    for db in sorted(workspace.folder("batteries").glob(f"*/{DB_NAME}")):
        status = battery_status(db.parent)
        found.append({"path": workspace.relative(db.parent), "total": status.total,
                      "counts": status.counts, "running": status.pid is not None})
    return {"batteries": found}


@router.post("")
def create(request: Request, body: BatteryBody) -> dict[str, Any]:
    """Check a battery and count its runs; unless ``dry_run``, write it and start it."""
    workspace: Workspace = request.app.state.workspace
    if not _NAME.match(body.name):
        raise HTTPException(400, f"name {body.name!r}: expected letters, digits, '.', '_' "
                                 "or '-' (a folder name)")
    if body.policy not in POLICIES:
        raise HTTPException(400, f"policy {body.policy!r}: expected {' or '.join(POLICIES)}")
    table: dict[str, Any] = {"name": body.name,
                             "algorithms": [_algorithm_entry(workspace, a)
                                            for a in body.algorithms],
                             "timeout": body.timeout, "policy": body.policy}
    if body.until is not None:
        table["until"] = body.until
    else:
        table["seeds"] = body.seeds
    if body.time is not None:
        table["time"] = body.time
    scenarios = [{"name": _scenario_ref(workspace, s.name), **s.params} for s in body.scenarios]
    if any("name" in s.params for s in body.scenarios):
        raise HTTPException(400, "scenario parameters: 'name' is not a parameter")
    data = {"battery": table, "scenarios": scenarios}
    source = workspace.folder("batteries") / f"{body.name}.toml"
    try:
        spec = spec_from_dict(data, workspace.folder("batteries"),
                              str(source) if not body.dry_run else "")
    except (TypeError, ValueError, KeyError, AttributeError) as exc:
        # the reader's checks raise MimicsError (422); a value of a type it did not
        # foresee is still the request's mistake, not the server's
        raise HTTPException(422, f"battery: {type(exc).__name__}: {exc}".splitlines()[0]) \
            from None
    runs = len(spec.runs())
    if body.dry_run:  # under a stopping rule: the first round, and at most
        return {"runs": runs} if spec.until is None else {
            "runs": runs, "max_runs": runs // spec.until.min_seeds * spec.until.max_seeds}
    folder = workspace.folder("batteries") / body.name
    if folder.exists():
        raise HTTPException(409, f"batteries/{body.name} exists already (choose another name)")
    source.write_text(tomli_w.dumps(data), encoding="utf-8")
    workers = request.app.state.battery_workers
    job = request.app.state.jobs.start(
        "battery", lambda job: run_battery(spec, folder, workers=workers, progress=False).line(),
        label=workspace.relative(folder))
    return {"runs": runs, "path": workspace.relative(folder), "job": job.id}


def _restart(request: Request, body: FolderBody, failed_only: bool) -> dict[str, Any]:
    workspace: Workspace = request.app.state.workspace
    folder = battery_folder(workspace, body.path)
    if lock_holder(folder) is not None:
        raise HTTPException(409, f"{body.path}: the battery is running already")
    workers = request.app.state.battery_workers
    go = rerun_failed if failed_only else resume_battery
    job = request.app.state.jobs.start(
        "battery", lambda job: go(folder, workers=workers, progress=False).line(),
        label=body.path)
    return {"path": body.path, "job": job.id}



@router.post("/resume")
def resume(request: Request, body: FolderBody) -> dict[str, Any]:
    """Go on with a stopped battery (after a restart of the server, a kill...)."""
    return _restart(request, body, failed_only=False)


@router.post("/rerun-failed")
def rerun(request: Request, body: FolderBody) -> dict[str, Any]:
    """Run the failed runs (error, timeout, crashed) of a stopped battery again."""
    return _restart(request, body, failed_only=True)


@router.get("/status")
def status(request: Request, path: str) -> dict[str, Any]:
    """Progress and the table of runs, from the battery's SQLite state."""
    from mimics.batteries.report import runs_table

    workspace: Workspace = request.app.state.workspace
    starting = [j for j in request.app.state.jobs.running("battery") if j.label == path]
    if starting and not (workspace.resolve(path) / DB_NAME).is_file():
        return {"path": path, "total": 0, "finished": 0, "counts": {}, "running": True,
                "rate": None, "eta": None, "errors": [], "runs": [], "starting": True}
    folder = battery_folder(workspace, path)
    state = battery_status(folder)
    table = runs_table(folder)
    rows: list[dict[str, Any]] = []
    if not table.empty:
        keep = ["id", "algorithm", "scenario", "parameters", "seed", "state", "misbehaving",
                "status", "reached_goal", "collisions", "deadlocks", "livelocks", "escaped",
                "exceptions", "sim_time", "wall_time", "attempts", "error", "folder"]
        rows = json.loads(table[[c for c in keep if c in table.columns]].to_json(
            orient="records"))
        for row in rows:
            real = Path(row["folder"])
            row["folder"] = workspace.relative(real) if real.is_dir() else None
    finished = state.total - state.left
    failed_jobs = [j for j in request.app.state.jobs.all("battery")
                   if j.label == path and j.state == "failed"]
    # A battery this server started counts as running from its start to its job's end:
    # between the database's creation and the driver's lock it has no lock holder yet.
    return {"path": path, "total": state.total, "finished": finished, "counts": state.counts,
            "running": state.pid is not None or bool(starting), "rate": state.rate,
            "eta": state.eta, "errors": [list(e) for e in state.errors], "runs": rows,
            "starting": False, "job_error": failed_jobs[-1].error if failed_jobs else ""}


@router.get("/plot")
def plot(request: Request, path: str, name: str) -> Response:
    """A battery figure (``outcomes.png``, ``time_to_goal.png``...), drawn by
    :func:`mimics.interfaces.plots.battery_plots` into a temporary folder (a GET writes
    nothing into the workspace)."""
    from mimics.interfaces.plots import battery_plots

    if name not in PLOTS:
        raise HTTPException(400, f"plot {name!r}: expected one of {', '.join(PLOTS)}")
    folder = battery_folder(request.app.state.workspace, path)
    with tempfile.TemporaryDirectory(prefix="mimics-plots-") as scratch:
        written, skipped = battery_plots(folder, scratch)
        target = Path(scratch) / name
        if target not in written:
            raise HTTPException(404, f"{name}: not drawn for this battery "
                                     f"({'; '.join(skipped) or 'no data'})")
        return Response(target.read_bytes(), media_type="image/png")


@router.get("/evidence")
def evidence(request: Request, path: str, baseline: str | None = None,
             metric: Annotated[list[str] | None, Query()] = None, exclude_failed: bool = False,
             adjust: str = "holm", interval: str = "t") -> dict[str, Any]:
    """Each cell's intervals, the paired comparison against a baseline (raw and adjusted
    p-values, the primary metric), the failed runs, the costs, the stopping rule's
    progress per cell (cells stopped short of their target named) and the identical-seed
    warnings (NaN as null)."""
    from mimics.batteries.evidence import battery_evidence

    folder = battery_folder(request.app.state.workspace, path)
    found = battery_evidence(folder, baseline=baseline, metrics=metric,
                             exclude_failed=exclude_failed, adjust=adjust, method=interval)
    table = found.table
    algorithms = list(dict.fromkeys(table["algorithm"])) if not table.empty else []
    rule = found.until
    cells = [c.as_dict() for c in found.cells]
    return {"path": path, "metrics": found.metrics, "algorithms": algorithms,
            "baseline": baseline or (algorithms[0] if algorithms else None),
            "primary": found.primary or None, "adjust": found.adjust, "tests": found.tests,
            "intervals": _records(found.intervals), "comparison": _records(found.comparison),
            "costs": _records(found.costs), "failed": found.failed, "unmet": found.unmet,
            "warnings": found.warnings,
            "until": None if rule is None else {
                "metric": rule.metric, "half_width": rule.half_width,
                "min_seeds": rule.min_seeds, "max_seeds": rule.max_seeds, "cells": cells}}


def _records(frame: Any) -> list[dict[str, Any]]:
    """Rows as JSON-ready dicts: NaN and infinities as null."""
    return json.loads(frame.to_json(orient="records"))
