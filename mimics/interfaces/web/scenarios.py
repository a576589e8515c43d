"""The Scenarios page's API: open, place robots, save, and run a scenario file; open a
built-in scenario as the start of a new file.

A scenario is saved as the TOML file ``mimics run`` reads, built from the
page's robots and checked by :func:`mimics.world.scenario_files.scenario_from_toml_text`
before anything is written (a scenario the CLI would refuse is not saved).
Runs go through :func:`mimics.records.runner.prepare` and ``run_to_folder``.
"""

from __future__ import annotations

import math
import os
import tomllib
from dataclasses import asdict, fields
from typing import Any

import numpy as np
import tomli_w
from fastapi import APIRouter, HTTPException, Request
from pydantic import Field

from mimics.catalog import list_scenarios, load_scenario
from mimics.interfaces.web.algorithms import algorithm_ref
from mimics.interfaces.web.bodies import StrictBody
from mimics.interfaces.web.jobs import Job
from mimics.interfaces.web.maps import check_extent, map_json, open_map, refuse_overwrite
from mimics.interfaces.web.security import Workspace
from mimics.interfaces.web.wording import paths_for_page, scenario_for_page
from mimics.world.errors import MimicsError
from mimics.world.limits import MAX_SEED, check_steps
from mimics.world.map_files import BUILTIN_MAPS, map_from_dict
from mimics.world.robot_types import BUILTIN_ROBOT_TYPES
from mimics.world.scenario import Settings
from mimics.world.scenario_files import (
    load_scenario_toml,
    random_placement,
    scenario_from_toml_text,
)

router = APIRouter(prefix="/api/scenarios", tags=["scenarios"])


class InlineMap(StrictBody):
    """A map written into the scenario file itself (a built-in scenario's generated map)."""

    name: str = "map"
    bounds: list[float] = Field(min_length=4, max_length=4)
    segments: list[list[float]] = Field(max_length=20_000)


class RobotBody(StrictBody):
    """One robot: its type, start pose (yaw in rad) and optional goal."""

    type: str
    x: float
    y: float
    yaw: float = 0.0
    goal: list[float] | None = Field(default=None, min_length=2, max_length=2)


class ScenarioBody(StrictBody):
    """A scenario to save under ``scenarios/`` (``.toml``): its map is a workspace map file,
    a built-in map name, or an inline map."""

    path: str
    name: str = "scenario"
    map: str | InlineMap
    robots: list[RobotBody] = Field(min_length=1, max_length=100_000)
    types: dict[str, dict[str, Any]] = Field(default_factory=dict)
    settings: dict[str, float | bool] = Field(default_factory=dict)
    # False: an existing file is kept and the answer is 409 (the page asks, then sends True)
    overwrite: bool = True


class PlaceBody(StrictBody):
    """Random placement of ``count`` robots of ``type`` in ``region`` on ``map``."""

    map: str | InlineMap
    type: str
    count: int = Field(ge=1, le=5000)
    region: list[float] | None = Field(default=None, min_length=4, max_length=4)
    min_spacing: float | None = Field(default=None, gt=0)
    seed: int = Field(default=0, ge=0, le=MAX_SEED)
    others: list[list[float]] = Field(default_factory=list)


class RunBody(StrictBody):
    """Run a saved scenario once."""

    path: str
    algorithm: str
    seed: int = Field(default=0, ge=0, le=MAX_SEED)
    time: float | None = Field(default=None, gt=0)
    # wall-clock seconds: a step that never returns is stopped there (engine/user_code/watchdog.py)
    wall_limit: float = Field(default=300.0, gt=0, le=86400)


def scenario_file(workspace: Workspace, path: str, must_exist: bool = True) -> Any:
    """The real path of a ``.toml`` under ``scenarios/``, else 400."""
    real = workspace.resolve(path, must_exist=must_exist)
    if workspace.folder("scenarios") not in real.parents or real.suffix != ".toml":
        raise HTTPException(400, f"{path}: scenarios are .toml files under scenarios/")
    return real


def _nan_free(values: list[float]) -> list[float] | None:
    return None if any(math.isnan(v) for v in values) else values


@router.get("")
def list_all(request: Request) -> dict[str, Any]:
    """The workspace's scenario files, the built-in scenarios, robot types and settings."""
    workspace: Workspace = request.app.state.workspace
    files = sorted(workspace.relative(p) for p in workspace.folder("scenarios").rglob("*.toml"))
    defaults = {f.name: getattr(Settings(), f.name) for f in fields(Settings)}
    return {"files": files,
            "builtin": [{"name": n, "description": d} for n, d in list_scenarios()],
            "robot_types": {name: asdict(t) for name, t in BUILTIN_ROBOT_TYPES.items()},
            "settings": {name: value for name, value in defaults.items()
                         if isinstance(value, bool | float | int) and math.isfinite(value)}}


@router.get("/file")
def get_scenario(request: Request, path: str) -> dict[str, Any]:
    """A scenario file as the page edits it: map, robots, types and settings."""
    workspace: Workspace = request.app.state.workspace
    real = scenario_file(workspace, path)
    scenario = load_scenario_toml(real)
    raw = tomllib.loads(real.read_text(encoding="utf-8"))
    raw_map = raw.get("map")
    map_ref = raw_map if isinstance(raw_map, str) else None
    if map_ref is not None and map_ref not in BUILTIN_MAPS:
        map_ref = workspace.relative((real.parent / map_ref).resolve())
    inline = isinstance(raw_map, dict) and "segments" in raw_map
    return {"path": path, **_editable(scenario, map_ref, inline),
            "custom_types": raw.get("types", {})}


def _editable(scenario: Any, map_ref: str | None, inline: bool) -> dict[str, Any]:
    """A scenario as the page edits it: name, map, robots, types, settings."""
    robots = [{"type": scenario.robot_type(i).name, "x": x, "y": y, "yaw": yaw,
               "goal": _nan_free(scenario.goals[i].tolist())}
              for i, (x, y, yaw, _v) in enumerate(scenario.stages.tolist())]
    types = {t.name: asdict(t) for t in scenario.types}
    settings = {f.name: getattr(scenario.settings, f.name) for f in fields(Settings)}
    settings = {k: v for k, v in settings.items() if not (isinstance(v, float)
                                                          and not math.isfinite(v))}
    data = map_json(scenario.map, map_ref or "")
    return {"name": scenario.name, "map": map_ref, "map_data": data,
            "map_inline": ({k: data[k] for k in ("name", "bounds", "segments")}
                           if inline else None),
            "robots": robots, "types": types, "settings": settings}


@router.get("/builtin")
def get_builtin(name: str) -> dict[str, Any]:
    """A built-in scenario (its default parameters) as the page edits it, to start a new
    file from: a generated map comes inline (``map_inline``); types that differ from the
    built-in ones of their name come whole in ``custom_types``."""
    known = dict(list_scenarios())
    if name not in known:
        raise HTTPException(400, f"scenario {name!r}: expected one of {', '.join(known)}")
    try:
        scenario = load_scenario(name)
    except MimicsError as exc:  # a Stage map whose data is not on this machine
        raise HTTPException(422, f"built-in scenario {name}: {exc}") from None
    source = str(scenario.map.source)
    map_ref = source if source in BUILTIN_MAPS else None
    custom = {}
    for robot_type in scenario.types:
        if BUILTIN_ROBOT_TYPES.get(robot_type.name) != robot_type:
            whole = asdict(robot_type)
            whole.pop("name")
            custom[robot_type.name] = whole
    return {"path": None, **_editable(scenario, map_ref, map_ref is None),
            "custom_types": custom}


def scenario_text(workspace: Workspace, body: ScenarioBody) -> tuple[Any, str]:
    """The real path and TOML text of the scenario the page sent."""
    real = scenario_file(workspace, body.path, must_exist=False)
    map_ref: str | dict[str, Any]
    if isinstance(body.map, InlineMap):
        check_extent(body.map.bounds, body.map.segments)
        map_ref = body.map.model_dump()
    elif body.map in BUILTIN_MAPS:
        map_ref = body.map
    else:
        map_real = workspace.resolve(body.map, must_exist=True)
        map_ref = os.path.relpath(map_real, real.parent).replace(os.sep, "/")
    robots = []
    for robot in body.robots:
        entry: dict[str, Any] = {"type": robot.type, "x": robot.x, "y": robot.y,
                                 "yaw": robot.yaw}
        if robot.goal is not None:
            entry["goal"] = list(robot.goal)
        robots.append(entry)
    data: dict[str, Any] = {"name": body.name, "map": map_ref, "robots": robots}
    if body.settings:
        data["settings"] = dict(body.settings)
    if body.types:
        data["types"] = body.types
    try:
        return real, tomli_w.dumps(data)
    except (TypeError, ValueError) as exc:
        raise HTTPException(400, f"scenario: cannot be written as TOML ({exc})") from None


@router.put("/file")
def put_scenario(request: Request, body: ScenarioBody) -> dict[str, Any]:
    """Check and save the scenario as the TOML file the CLI runs."""
    workspace: Workspace = request.app.state.workspace
    real, text = scenario_text(workspace, body)
    try:  # the CLI's own checks, before writing; their message in the page's words
        scenario = scenario_from_toml_text(text, real)
    except MimicsError as exc:
        raise HTTPException(422, scenario_for_page(paths_for_page(str(exc), workspace.root),
                                                   body.types)) from None
    refuse_overwrite(real, body.path, body.overwrite)
    real.parent.mkdir(parents=True, exist_ok=True)
    real.write_text(text, encoding="utf-8")
    return {"path": workspace.relative(real), "robots": scenario.robot_count}


@router.post("/place")
def place(request: Request, body: PlaceBody) -> dict[str, Any]:
    """Random start poses in free space, ``min_spacing`` apart and from ``others``."""
    if body.type not in BUILTIN_ROBOT_TYPES:
        raise HTTPException(400, f"type {body.type!r}: expected one of "
                                 f"{', '.join(BUILTIN_ROBOT_TYPES)}")
    if isinstance(body.map, InlineMap):
        check_extent(body.map.bounds, body.map.segments)
        try:
            the_map = map_from_dict(body.map.model_dump(), "map")
        except MimicsError as exc:
            raise HTTPException(422, str(exc)) from None
    else:
        the_map = open_map(request, body.map)
    others = np.array(body.others, dtype=float).reshape(-1, 2) if body.others else None
    poses = random_placement(body.count, BUILTIN_ROBOT_TYPES[body.type], the_map,
                             np.random.default_rng(body.seed),
                             region=tuple(body.region) if body.region else None,
                             min_spacing=body.min_spacing, others=others)
    return {"poses": poses.tolist()}


def run_scenario(workspace: Workspace, job: Job, scenario: str, algorithm: str, seed: int,
                 time: float | None, wall_limit: float | None = None) -> dict[str, Any]:
    """Run once and record into ``runs/NAME-ALGORITHM-sSEED`` (reported to ``job``), or
    ``-2``, ``-3``... when that folder is taken: a run never replaces another."""
    from mimics.records.naming import new_run_folder
    from mimics.records.runner import prepare, run_to_folder

    sim = prepare(scenario, algorithm, seed=seed, time=time, wall_limit=wall_limit)
    folder = new_run_folder(workspace.folder("runs"), sim.scenario.name, sim.controller.name,
                            seed)
    limit = sim.scenario.settings.time_limit if time is None else time
    total = max(1, round(limit / sim.scenario.settings.dt))

    class Progress:
        def on_step(self, sim: Any) -> None:
            job.progress(int(sim.state.step), total)

    sim.observers.append(Progress())
    result = run_to_folder(sim, folder)
    return {"run": workspace.relative(folder), "status": result.status, "error": result.error}


@router.post("/run")
def run(request: Request, body: RunBody) -> dict[str, Any]:
    """Start one run of a saved scenario; poll ``/api/jobs/{id}`` for its run folder."""
    workspace: Workspace = request.app.state.workspace
    real = scenario_file(workspace, body.path)
    ref = algorithm_ref(workspace, body.algorithm)
    scenario = load_scenario_toml(real)  # a broken file fails here, before the job
    if body.time is not None:  # a time past the step counter: refused now, not in the job
        check_steps(body.time, scenario.settings.dt)
    job = request.app.state.jobs.start(
        "run", lambda job: run_scenario(workspace, job, str(real), ref, body.seed, body.time,
                                        body.wall_limit))
    return job.as_dict()
