"""The live runs' API: start a run in a worker process, control it, edit it, stream it.

A live run steps in a process of its own (:mod:`mimics.interfaces.web.live_worker`)
and records a normal run folder under ``runs/`` (a new one: never one taken).
The page watches it over the WebSocket ``/api/live/{id}/stream``, which sends:

* text messages, JSON: ``{"type": "meta", ...}`` (map, goals, robot sizes,
  colours, ``dt``; again whenever an edit changes walls or goals) and
  ``{"type": "state", ...}`` (what ``GET /api/live/{id}`` returns) when the
  state, speed or error change; ``{"type": "moved", "robot": i, "step": s}`` when an
  edit moved robot ``i`` (before the frame that shows it: the page breaks its trail);
* binary messages: one frame each, in the replay's layout
  (:mod:`mimics.interfaces.web.live_frames`, T = 1): the latest frame when the
  page is ready for one, so a slow page skips frames and slows nobody.

The socket closes (code 1000) after the last frame of a run that has ended.
``GET /api/live/{id}/frame`` returns the latest frame for clients without
WebSockets. The workbench's guards hold: the WebSocket is refused (403 at the
handshake) for a Host not served or an Origin of another site.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import math
from pathlib import Path
from typing import Any, Literal

from fastapi import (
    APIRouter,
    Depends,
    HTTPException,
    Query,
    Request,
    WebSocket,
    WebSocketDisconnect,
)
from fastapi.responses import Response
from pydantic import Field

from mimics.catalog import list_scenarios
from mimics.interfaces.web.algorithms import algorithm_ref
from mimics.interfaces.web.bodies import StrictBody, no_fields
from mimics.interfaces.web.live_runs import ENDED, LiveRefused, LiveRun, LiveRuns
from mimics.interfaces.web.security import Workspace, websocket_refusal
from mimics.interfaces.web.wording import paths_for_page
from mimics.world.limits import MAX_SEED

router = APIRouter(prefix="/api/live", tags=["live"])
SPEED_RANGE = (0.1, 100.0)  # factors of real time the page offers
EDIT_KINDS = ("move_robot", "add_wall", "remove_wall", "set_goal", "remove_robot")
#: Decimals an edit's numbers are rounded to: positions to the millimetre, headings to the
#: milliradian (0.057 degrees), so that scenario.toml records what was meant
#: (``x = 2.0``, not the screen's ``2.0000003317128052``) and reads back exactly.
POSITION_DECIMALS = 3
HEADING_DECIMALS = 3


class LiveBody(StrictBody):
    """Start a live run: a saved scenario (or a built-in) with an algorithm and a seed,
    or the run ``run`` of the battery ``battery`` (its scenario, parameters, algorithm,
    seed and time)."""

    scenario: str | None = None
    algorithm: str | None = None
    seed: int = Field(default=0, ge=0, le=MAX_SEED)
    time: float | None = Field(default=None, gt=0)
    speed: float | Literal["fastest"] = 1.0
    # wall-clock seconds from the start, pauses included, as `mimics run --wall-limit`
    wall_limit: float | None = Field(default=None, gt=0, le=86400)
    paused: bool = False
    fps: float = Field(default=60.0, gt=0, le=120)
    battery: str | None = None
    run: int | None = Field(default=None, ge=1, le=MAX_SEED)


class SpeedBody(StrictBody):
    """A factor of real time (0.1 to 100), or ``"fastest"``."""

    speed: float | Literal["fastest"]


def runs_of(request: Request | WebSocket) -> LiveRuns:
    return request.app.state.live


def check_speed(speed: float | str) -> float:
    """The speed as simulated seconds per wall second (``inf`` for ``"fastest"``), else 422."""
    if speed == "fastest":
        return math.inf
    low, high = SPEED_RANGE
    if not isinstance(speed, int | float) or not low <= speed <= high:
        raise HTTPException(422, f"speed: expected a factor of real time from {low:g} to "
                                 f"{high:g}, or \"fastest\"; got {speed!r}")
    return float(speed)


def _refused(exc: LiveRefused) -> HTTPException:
    return HTTPException(exc.status, str(exc))


def described(workspace: Workspace, run: LiveRun) -> dict[str, Any]:
    """The run's state with its folder, and the paths in its error, relative to the
    workspace (as the CLI words the error, but for the page)."""
    out = run.as_dict()
    out["error"] = paths_for_page(out["error"], workspace.root)
    if out["run"]:
        with contextlib.suppress(ValueError):
            out["run"] = workspace.relative(Path(out["run"]))
    return out


def _what_to_run(workspace: Workspace, body: LiveBody) -> tuple[dict[str, Any], dict[str, Any]]:
    """The worker's request (real paths) and the label shown in lists (workspace's names)."""
    if body.battery is not None:
        return _battery_row(workspace, body)
    if not body.scenario or not body.algorithm:
        raise HTTPException(422, "a live run needs a scenario and an algorithm (or a battery "
                                 "and one of its runs)")
    builtin = [n for n, _ in list_scenarios()]
    if body.scenario in builtin:
        scenario = body.scenario
    else:
        real = workspace.resolve(body.scenario) if body.scenario.endswith(".toml") else None
        if (real is None or workspace.folder("scenarios") not in real.parents
                or not real.is_file()):
            raise HTTPException(400, f"scenario {body.scenario!r}: expected a built-in "
                                     f"({', '.join(builtin)}) or a .toml file under scenarios/")
        scenario = str(real)
    request = {"scenario": scenario, "algorithm": algorithm_ref(workspace, body.algorithm),
               "seed": body.seed, "time": body.time, "params": None, "policy": "abort"}
    return request, {"scenario": body.scenario, "algorithm": body.algorithm, "seed": body.seed}


def _battery_row(workspace: Workspace, body: LiveBody) -> tuple[dict[str, Any], dict[str, Any]]:
    """The request of run ``body.run`` of the battery ``body.battery`` (as its worker would
    run it: the same scenario, parameters, algorithm, seed, time and policy)."""
    from mimics.batteries.store import BatteryStore
    from mimics.interfaces.web.batteries import battery_folder

    if body.run is None:
        raise HTTPException(422, "battery: give the id of one of its runs in run")
    folder = battery_folder(workspace, body.battery or "")
    store = BatteryStore.open(folder)
    try:
        rows = {row["id"]: row for row in store.rows()}
        if body.run not in rows:
            raise HTTPException(404, f"{body.battery}: no run {body.run}")
        task = store.task(body.run, 0, store.spec(), folder)
    finally:
        store.close()
    row = rows[body.run]
    request = {"scenario": task.scenario, "algorithm": task.algorithm, "seed": task.seed,
               "time": body.time or task.time, "params": task.params, "policy": task.policy}
    label = {"scenario": row["scenario"], "algorithm": row["algorithm"], "seed": task.seed,
             "battery": body.battery, "battery_run": body.run}
    return request, label


@router.post("")
def start(request: Request, body: LiveBody) -> dict[str, Any]:
    """Start a live run in a worker process; answers once the run is prepared (or 422 with
    the one-line reason it could not be: a bad scenario, algorithm or option)."""
    workspace: Workspace = request.app.state.workspace
    speed = check_speed(body.speed)
    worker_request, label = _what_to_run(workspace, body)
    worker_request.update(speed=speed, wall_limit=body.wall_limit, fps=body.fps,
                          paused=body.paused, runs=str(workspace.folder("runs")))
    try:
        run = runs_of(request).start(worker_request, {**label, "started_paused": body.paused})
    except LiveRefused as exc:
        raise _refused(exc) from None
    run.wait_ready()
    if run.state == "error" and not run.run:  # it never started: a bad input, one line
        raise HTTPException(422, paths_for_page(run.error, workspace.root))
    return described(workspace, run)


@router.get("")
def list_live(request: Request) -> dict[str, Any]:
    """This server's live runs, newest first (going and ended)."""
    workspace: Workspace = request.app.state.workspace
    return {"live": [described(workspace, r) for r in runs_of(request).all()]}


def rounded_edit(body: dict[str, Any]) -> dict[str, Any]:
    """``body`` with its positions (``x``, ``y``, ``segment``, ``rectangle``, ``at``)
    rounded to :data:`POSITION_DECIMALS` and ``yaw`` to :data:`HEADING_DECIMALS`; what
    is not a finite number is left for the edit's reader to refuse by name.

    >>> rounded_edit({"kind": "move_robot", "robot": 0, "x": 2.0000003317128052,
    ...               "y": -0.01124771, "yaw": 1.5707963})
    {'kind': 'move_robot', 'robot': 0, 'x': 2.0, 'y': -0.011, 'yaw': 1.571}
    """
    def rounded(value: Any, decimals: int) -> Any:
        if isinstance(value, float) and math.isfinite(value):
            return round(value, decimals) + 0.0  # (+ 0.0: no -0.0 in the record)
        return value

    out = dict(body)
    for name in ("x", "y", "yaw"):
        if name in out:
            out[name] = rounded(out[name], HEADING_DECIMALS if name == "yaw"
                                else POSITION_DECIMALS)
    for name in ("segment", "rectangle", "at"):
        if isinstance(out.get(name), list):
            out[name] = [rounded(v, POSITION_DECIMALS) for v in out[name]]
    return out


def _run(request: Request, run_id: int) -> LiveRun:
    try:
        return runs_of(request).get(run_id)
    except LiveRefused as exc:
        raise _refused(exc) from None


@router.get("/{run_id}")
def get_live(request: Request, run_id: int) -> dict[str, Any]:
    """A live run's ``state`` (starting, running, paused, finished, error), ``step``,
    ``time``, ``speed``, ``run`` (its folder), ``status`` and ``error``. Its frames come
    over the WebSocket ``/api/live/{run_id}/stream`` (see the module's docs)."""
    return described(request.app.state.workspace, _run(request, run_id))


@router.get("/{run_id}/meta")
def get_meta(request: Request, run_id: int) -> dict[str, Any]:
    """The map, goals, robot sizes, colours and ``dt`` of a live run (as streamed)."""
    return _run(request, run_id).meta


@router.get("/{run_id}/frame")
def get_frame(request: Request, run_id: int) -> Response:
    """The latest frame of a live run in the replay's binary layout (one frame)."""
    frame = _run(request, run_id).frame
    if frame is None:
        raise HTTPException(404, f"live run {run_id}: no frame yet")
    return Response(frame, media_type="application/octet-stream")


@router.get("/{run_id}/robot")
def get_robot(request: Request, run_id: int, robot: int) -> dict[str, Any]:
    """Robot ``robot`` now, for the inspector: ``id``, ``type``, ``state``, ``time``, ``x``,
    ``y``, ``yaw``, ``v``, ``w``, ``vRef``, ``headingRef``, ``goal``, and ``lines``: its
    events so far (its per-robot log is written when the run ends), the last 2,000,
    ``skipped`` counting those left out. Once the run has ended: as last seen, with
    ``final`` true (a request in flight at the end is answered, not refused)."""
    try:
        return _run(request, run_id).robot(robot)
    except LiveRefused as exc:
        raise _refused(exc) from None


@router.get("/{run_id}/beams")
def get_beams(request: Request, run_id: int, robot: int | None = None,
              every_robot: bool = Query(False, alias="all")) -> dict[str, Any]:
    """The laser beams of robot ``robot``'s last scan, or with ``all=true`` of every active
    robot's, as the engine sensed them (the ranges the algorithm reads, noise included):
    ``segments`` ``[x0, y0, x1, y1]`` from each robot's pose now, ``every`` (each robot's
    every k-th beam, so that at most 60,000 come), ``step`` and ``time``. An inactive
    robot or one without a ranger has none; nor has a run that has ended (``final``
    true: the page keeps the beams it drew)."""
    if every_robot == (robot is not None):
        raise HTTPException(422, "beams: give either robot=N or all=true")
    try:
        return _run(request, run_id).beams(None if every_robot else robot)
    except LiveRefused as exc:
        raise _refused(exc) from None


def _control(request: Request, run_id: int, name: str, argument: Any = None) -> dict[str, Any]:
    try:
        _run(request, run_id).command(name, argument)
    except LiveRefused as exc:
        raise _refused(exc) from None
    return described(request.app.state.workspace, _run(request, run_id))


@router.post("/{run_id}/pause", dependencies=[Depends(no_fields)])
def pause(request: Request, run_id: int) -> dict[str, Any]:
    """Stop stepping after the current step."""
    return _control(request, run_id, "pause")


@router.post("/{run_id}/resume", dependencies=[Depends(no_fields)])
def resume(request: Request, run_id: int) -> dict[str, Any]:
    """Step on at the run's speed."""
    return _control(request, run_id, "play")


@router.post("/{run_id}/step", dependencies=[Depends(no_fields)])
def step(request: Request, run_id: int) -> dict[str, Any]:
    """Pause (if running), then take exactly one step; answers once it is taken."""
    return _control(request, run_id, "step")


@router.post("/{run_id}/stop", dependencies=[Depends(no_fields)])
def stop(request: Request, run_id: int) -> dict[str, Any]:
    """End the run where it is, without another step (status ``stopped``, recorded in its
    scenario.toml as its end, so that ``mimics run RUN/scenario.toml ALGO --seed S`` re-runs
    it bit for bit). Answers once the run has ended and its folder is complete (state
    ``finished``), or with the state ``stopping`` should its last step take a few seconds
    more."""
    return _control(request, run_id, "stop")


@router.post("/{run_id}/speed")
def speed(request: Request, run_id: int, body: SpeedBody) -> dict[str, Any]:
    """Real time is 1; a factor from 0.1 to 100, or ``"fastest"`` (no pacing)."""
    return _control(request, run_id, "speed", check_speed(body.speed))


@router.post("/{run_id}/edit")
def edit(request: Request, run_id: int, body: dict[str, Any]) -> dict[str, Any]:
    """Apply an edit at the next step boundary (``kind``: move_robot, add_wall,
    remove_wall, set_goal, remove_robot, with its fields); returns the applied edit with
    its step and time, or 422 with the one-line reason it was refused. Positions are
    rounded to the millimetre and headings to the milliradian (:func:`rounded_edit`).
    Edits are recorded in the run's events.parquet and scenario.toml."""
    if body.get("kind") not in EDIT_KINDS:
        raise HTTPException(422, f"edit kind {body.get('kind')!r}: expected one of "
                                 f"{', '.join(EDIT_KINDS)}")
    try:
        return _run(request, run_id).edit(rounded_edit(body))
    except LiveRefused as exc:
        raise _refused(exc) from None


@router.websocket("/{run_id}/stream")
async def stream(websocket: WebSocket, run_id: int) -> None:
    """The run's meta, state and frames as they come (see the module's docs)."""
    refusal = websocket_refusal(websocket.headers, websocket.app.state.served_hosts)
    if refusal is not None:
        await websocket.close(code=1008, reason=refusal)  # before accept: 403 at the handshake
        return
    try:
        run = runs_of(websocket).get(run_id)
    except LiveRefused as exc:
        await websocket.close(code=1008, reason=str(exc))
        return
    await websocket.accept()
    workspace: Workspace = websocket.app.state.workspace
    changed = run.watch()
    closed = asyncio.Event()

    async def until_closed() -> None:  # the page's messages are not used; its close is
        with contextlib.suppress(WebSocketDisconnect, RuntimeError):
            while (await websocket.receive())["type"] != "websocket.disconnect":
                pass
        closed.set()
        changed.set()

    reader = asyncio.create_task(until_closed())
    sent_meta = sent_frame = -1
    sent_moves = 0
    sent_state: tuple[Any, ...] = ()
    try:
        while not closed.is_set():
            await changed.wait()
            changed.clear()
            if closed.is_set():
                break
            if run.meta_version != sent_meta and run.meta:
                sent_meta = run.meta_version
                await websocket.send_text(json.dumps({"type": "meta", **run.meta}))
            state = described(workspace, run)
            key = tuple(state[k] for k in ("state", "speed", "error", "status", "run"))
            if key != sent_state:
                sent_state = key
                await websocket.send_text(json.dumps({"type": "state", **state}))
            for robot, at_step in run.moves[sent_moves:]:  # before the frame that shows it
                sent_moves += 1
                await websocket.send_text(json.dumps({"type": "moved", "robot": robot,
                                                      "step": at_step}))
            frame, version = run.frame, run.frame_version
            if frame is not None and version != sent_frame:
                sent_frame = version
                await websocket.send_bytes(frame)
            if (run.state in ENDED and sent_frame == run.frame_version
                    and sent_meta == run.meta_version):
                await websocket.close(code=1000)
                break
    except (WebSocketDisconnect, RuntimeError):
        pass  # the page went away: the run goes on
    finally:
        run.unwatch(changed)
        reader.cancel()
