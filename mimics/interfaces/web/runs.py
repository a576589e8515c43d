"""The Runs page's API: list run folders, send a replay in binary, beams, logs, video, plot.

The replay's arrays come from :func:`mimics.interfaces.replay.replay_data` (the
replay's own reader of a run folder). ``/api/runs/frames`` sends them as one
little-endian binary body in the layout of :mod:`mimics.interfaces.web.live_frames`
(which writes it, for the live stream too). A long run is thinned to every k-th
recorded step (always keeping the last) so that the body stays under
:data:`FRAME_BYTES`; ``/api/runs/meta`` tells k.

The inspector's routes work on those frames: ``/api/runs/robot`` gives one
robot's speed, turn rate and references at every frame sent (from
trajectory.parquet's ``v``, ``w``, ``v_ref``, ``heading_ref``),
``/api/runs/beams`` one robot's beams at a frame and ``/api/runs/all_beams``
every robot's, and ``/api/runs/log?until=T`` a robot's log lines up to time T.

A run edited as it ran: ``/api/runs/meta`` gives its wall sets once (``walls``: the
first frame sent that shows each set, its step, its segments), its goals likewise
(``goal_sets``, after ``set_goal`` edits) and the frames where an edit moved a robot
(``moves``: robot and the first frame at its new place, where the page breaks its
trail); the beams of a frame are cast against its walls.
"""

from __future__ import annotations

import functools
import math
import re
import tempfile
from pathlib import Path
from typing import Any

import numpy as np
from fastapi import APIRouter, HTTPException, Request
from fastapi.responses import FileResponse, Response
from pydantic import Field

from mimics.engine.state import Status
from mimics.interfaces.render import STATUS_COLORS
from mimics.interfaces.replay import (
    MOTION_COLUMNS,
    BeamCaster,
    ReplayData,
    export_replay,
    replay_data,
    robot_motion,
)
from mimics.interfaces.web.bodies import StrictBody
from mimics.interfaces.web.live_frames import encode_frames, frame_states
from mimics.interfaces.web.security import Workspace
from mimics.records.layout import SCENARIO_TOML, SUMMARY_JSON
from mimics.records.run_folder import load_run
from mimics.world.limits import MAX_ROBOTS
from mimics.world.map_files import map_to_dict

router = APIRouter(prefix="/api/runs", tags=["runs"])
FRAME_BYTES = 64_000_000  # largest frames body; Hospital x 2,000 robots x 600 s fits thinned
EVENT_LIMIT = 20_000  # events sent for the time bar and the logs
LOG_LINES = 2000  # log lines sent: the last ones up to the time asked
ALL_BEAMS = 60_000  # beams sent for every robot at once: each robot's are thinned to fit
_LOG_ROW = re.compile(r"^(-?[0-9.]+(?:[eE][-+]?[0-9]+)?);")  # a data row of a robot's log
VIDEO_NAME = "replay.mp4"


class ExportBody(StrictBody):
    """Export a run's replay as ``replay.mp4`` in its folder."""

    path: str
    speed: float = Field(default=1.0, gt=0, le=1000)
    fps: float = Field(default=10.0, gt=0, le=60)
    robot: int | None = Field(default=None, ge=0, lt=MAX_ROBOTS)


def run_folder(workspace: Workspace, path: str) -> Path:
    """The real path of a run folder of the workspace, else 400."""
    real = workspace.resolve(path, must_exist=True)
    if not real.is_dir() or not ((real / SUMMARY_JSON).is_file()
                                 or (real / SCENARIO_TOML).is_file()):
        raise HTTPException(400, f"{path}: not a run folder")
    return real


@functools.lru_cache(maxsize=2)
def _replay(folder: Path, stamp: float) -> tuple[ReplayData, Any, int]:
    """The run's replay arrays, its events and the thinning step (kept for the last 2 runs)."""
    run = load_run(folder)
    data = replay_data(run)
    frame_bytes = data.n * 13 + 4
    stride = max(1, math.ceil(len(data.times) * frame_bytes / FRAME_BYTES))
    return data, run.events, stride


@functools.lru_cache(maxsize=2)
def _caster(folder: Path, stamp: float) -> BeamCaster:
    """The run's beam caster (a wall index is built once per wall set of the run)."""
    data = _replay(folder, stamp)[0]
    assert data.walls is not None
    return BeamCaster(data.scenario, data.walls.sets)


def _stamp(folder: Path) -> float:
    marker = folder / SUMMARY_JSON
    return marker.stat().st_mtime if marker.exists() else 0.0


def replay_of(workspace: Workspace, path: str) -> tuple[ReplayData, Any, int]:
    """The cached replay of a run folder (re-read when its summary changes)."""
    folder = run_folder(workspace, path)
    return _replay(folder, _stamp(folder))


def _frame_step(data: ReplayData, stride: int, frame: int) -> int:
    """The recorded step shown at frame ``frame`` of the frames sent, else 400."""
    index = _frames(data, stride)
    if not 0 <= frame < len(index):
        raise HTTPException(400, f"frame {frame} is not in the run (0..{len(index) - 1})")
    return int(index[frame])


def _frames(data: ReplayData, stride: int) -> np.ndarray:
    index = np.arange(0, len(data.times), stride)
    if index[-1] != len(data.times) - 1:
        index = np.append(index, len(data.times) - 1)
    return index


@router.get("")
def list_runs(request: Request) -> dict[str, Any]:
    """Run folders under ``runs/`` and in the batteries, newest first, with their outcome."""
    workspace: Workspace = request.app.state.workspace
    found = []
    folders = [*workspace.folder("runs").glob("*/"),
               *workspace.folder("batteries").glob("*/runs/*/")]
    for folder in folders:
        if not ((folder / SUMMARY_JSON).is_file() or (folder / SCENARIO_TOML).is_file()):
            continue
        entry: dict[str, Any] = {"path": workspace.relative(folder),
                                 "modified": folder.stat().st_mtime}
        try:
            summary = load_run(folder).summary
            entry.update({k: summary.get(k) for k in ("scenario", "algorithm", "seed", "robots",
                                                     "status", "sim_time")})
        except Exception as exc:  # a broken run is listed with its message
            entry["error"] = str(exc)
        found.append(entry)
    found.sort(key=lambda e: -e["modified"])
    return {"runs": found}


@router.get("/meta")
def meta(request: Request, path: str) -> dict[str, Any]:
    """Everything but the frames: summary, map, robot sizes, goals, events, colours."""
    workspace: Workspace = request.app.state.workspace
    data, events, stride = replay_of(workspace, path)
    run = load_run(run_folder(workspace, path))
    half_length, half_width = data.half_sizes
    goals = data.scenario.goals
    rows = []
    if events is not None and len(events):
        shown = events.head(EVENT_LIMIT)
        rows = [{"time": float(t), "robot": int(r), "kind": str(k), "detail": str(d)}
                for t, r, k, d in zip(shown["time"], shown["robot"], shown["kind"],
                                      shown["detail"], strict=True)]
    return {"path": path, "summary": run.summary, "title": data.title, "robots": data.n,
            "duration": data.duration, "stride": stride,
            "frames": len(_frames(data, stride)), "map": map_to_dict(data.scenario.map),
            "half_length": half_length.tolist(), "half_width": half_width.tolist(),
            "goals": _goal_list(goals),
            "beams": [int(data.scenario.robot_type(i).ranger.beams) for i in range(data.n)],
            "types": [data.scenario.robot_type(i).name for i in range(data.n)],
            "events": rows, "colors": STATUS_COLORS,
            "video": (run.path / VIDEO_NAME).is_file(), **edited_world(data, stride)}


def edited_world(data: ReplayData, stride: int) -> dict[str, Any]:
    """What the edits of a run change in the frames sent: ``walls``, each wall set with
    the first frame that shows it (``frame``), its ``step`` and ``segments`` (one set for
    a run without wall edits); ``goal_sets``, the goals likewise (``goals``: ``[x, y]``
    or null per robot); and ``moves``: ``[robot, frame]`` for each robot an edit moved,
    the frame the first at its new place."""
    assert data.walls is not None and data.moves is not None and data.steps is not None
    assert data.goals is not None
    sent = data.steps[_frames(data, stride)]

    def shown(timeline: Any, name: str, value: Any) -> list[dict[str, Any]]:
        entries = []
        for step, values in zip(timeline.steps.tolist(), timeline.sets, strict=True):
            frame = int(np.searchsorted(sent, step, side="left"))
            if frame < len(sent):  # a set after the last frame is never shown
                entries.append({"frame": frame, "step": step, name: value(values)})
        return entries

    moves = [[robot, int(np.searchsorted(sent, step, side="right"))]
             for robot, steps in sorted(data.moves.items()) for step in steps.tolist()]
    return {"walls": shown(data.walls, "segments", lambda walls: walls.tolist()),
            "goal_sets": shown(data.goals, "goals", _goal_list),
            "moves": [m for m in moves if m[1] < len(sent)]}


def _goal_list(goals: np.ndarray) -> list[list[float] | None]:
    return [None if math.isnan(g[0]) else [float(g[0]), float(g[1])] for g in goals.tolist()]


@router.get("/frames")
def frames(request: Request, path: str) -> Response:
    """The replay in the binary layout of the module docstring."""
    data, _events, stride = replay_of(request.app.state.workspace, path)
    index = _frames(data, stride)
    body = encode_frames(data.times[index], data.pose[index],
                         frame_states(data.status[index], data.livelock[index]))
    return Response(body, media_type="application/octet-stream")


@router.get("/robot")
def robot(request: Request, path: str, robot: int) -> dict[str, Any]:
    """Robot ``robot``'s speed ``v`` (m/s), turn rate ``w`` (rad/s) and the references its
    code returned (``v_ref`` m/s, ``heading_ref`` rad) at each frame sent (null before its
    first row)."""
    workspace: Workspace = request.app.state.workspace
    data, _events, stride = replay_of(workspace, path)
    if not 0 <= robot < data.n:
        raise HTTPException(400, f"robot {robot}: the run has robots 0..{data.n - 1}")
    run = load_run(run_folder(workspace, path))
    motion = robot_motion(run, robot, data.times)[_frames(data, stride)]
    return {"robot": robot, "type": data.scenario.robot_type(robot).name,
            **{name: [None if math.isnan(v) else float(v) for v in motion[:, k]]
               for k, name in enumerate(MOTION_COLUMNS)}}


@router.get("/beams")
def beams(request: Request, path: str, robot: int, frame: int) -> dict[str, Any]:
    """Robot ``robot``'s laser beams at frame ``frame``, recomputed from the logged poses
    (the replay's :class:`~mimics.interfaces.replay.BeamCaster`; noise-free)."""
    workspace: Workspace = request.app.state.workspace
    data, _events, stride = replay_of(workspace, path)
    if not 0 <= robot < data.n:
        raise HTTPException(400, f"robot {robot} or frame {frame} is not in the run")
    k = _frame_step(data, stride, frame)
    folder = run_folder(workspace, path)
    segments = _caster(folder, _stamp(folder)).beams(robot, data.pose[k], data.status[k],
                                                     int(data.wall_set[k]))
    return {"segments": [] if segments is None else segments.reshape(-1, 4).tolist()}


@router.get("/all_beams")
def all_beams(request: Request, path: str, frame: int) -> dict[str, Any]:
    """Every active robot's beams at frame ``frame`` (the same caster as ``/beams``, one
    scan); ``every``: each robot's every k-th beam, so that at most :data:`ALL_BEAMS` come."""
    workspace: Workspace = request.app.state.workspace
    data, _events, stride = replay_of(workspace, path)
    k = _frame_step(data, stride, frame)
    folder = run_folder(workspace, path)
    caster = _caster(folder, _stamp(folder))
    total = int(caster.types.beam_count[data.status[k] == Status.ACTIVE].sum())
    every = max(1, math.ceil(total / ALL_BEAMS))
    segments = caster.all_beams(data.pose[k], data.status[k], every, int(data.wall_set[k]))
    return {"segments": np.round(segments.reshape(-1, 4), 4).tolist(), "every": every}


def _slack(until: float) -> float:
    """How far past ``until`` a row still counts as at it: the page's frame times are
    float32 (2.1 s comes as 2.0999999), a millionth of the time is below any step."""
    return 1e-6 * max(1.0, abs(until))


def log_until(lines: list[str], until: float | None) -> tuple[list[str], int]:
    """A robot log's lines up to simulated time ``until`` (all when None): the header, then
    the last :data:`LOG_LINES` rows at or before ``until`` (a quoted message's continued
    lines stay with its row), then the closing lines once every row is shown. Also returns
    how many earlier rows were left out."""
    header: list[str] = []
    rows: list[list[str]] = []
    closing: list[str] = []
    quotes = 0  # odd: the row goes on over the next line (a quoted line break)
    for line in lines:
        if quotes % 2:
            rows[-1].append(line)
            quotes += line.count('"')
        elif _LOG_ROW.match(line):
            rows.append([line])
            quotes = line.count('"')
        elif rows:
            closing.append(line)
        else:
            header.append(line)
    times = [float(_LOG_ROW.match(row[0]).group(1)) for row in rows]  # type: ignore[union-attr]
    shown = len(rows) if until is None else sum(t <= until + _slack(until) for t in times)
    first = max(0, shown - LOG_LINES)
    body = [line for row in rows[first:shown] for line in row]
    return header + body + (closing if shown == len(rows) else []), first


@router.get("/log")
def log(request: Request, path: str, robot: int, until: float | None = None) -> dict[str, Any]:
    """Robot ``robot``'s lines up to simulated time ``until`` (all when not given): its
    per-robot text log when written, else its events; ``skipped``: earlier lines left out."""
    if until is not None and not math.isfinite(until):
        raise HTTPException(422, f"until: expected a finite time in s, got {until}")
    workspace: Workspace = request.app.state.workspace
    run = load_run(run_folder(workspace, path))
    if not 0 <= robot < run.robot_count:
        raise HTTPException(400, f"robot {robot}: the run has robots 0..{run.robot_count - 1}")
    log_file = run.log_path(robot)
    if log_file.is_file():
        lines, skipped = log_until(
            log_file.read_text(encoding="utf-8", errors="replace").splitlines(), until)
        return {"source": "log", "lines": lines, "skipped": skipped}
    events = run.events
    mine = events[events["robot"] == robot]
    if until is not None:
        mine = mine[mine["time"] <= until + _slack(until)]
    skipped = max(0, len(mine) - LOG_LINES)
    mine = mine.tail(LOG_LINES)
    return {"source": "events", "skipped": skipped,
            "lines": [f"{t:.2f} s  {k}: {d}" for t, k, d in
                      zip(mine["time"], mine["kind"], mine["detail"], strict=True)]}


@router.post("/export")
def export(request: Request, body: ExportBody) -> dict[str, Any]:
    """Write ``replay.mp4`` into the run folder with the existing renderer; poll the job."""
    workspace: Workspace = request.app.state.workspace
    folder = run_folder(workspace, body.path)

    def work(job: Any) -> dict[str, Any]:
        result = export_replay(folder, video=folder / VIDEO_NAME, fps=body.fps,
                               speed=body.speed, robot_beams=body.robot, progress=False,
                               on_frame=job.progress)
        return {"video": workspace.relative(result.paths[0]), "frames": result.frames}

    return request.app.state.jobs.start("export", work).as_dict()


@router.get("/video")
def video(request: Request, path: str) -> FileResponse:
    """The run's exported ``replay.mp4``."""
    target = run_folder(request.app.state.workspace, path) / VIDEO_NAME
    if not target.is_file():
        raise HTTPException(404, f"{path}: no video exported yet")
    return FileResponse(target, media_type="video/mp4")


@router.get("/plot")
def plot(request: Request, path: str) -> Response:
    """The run's trajectories over the map (:func:`mimics.interfaces.plots.plot_run`),
    drawn into a temporary file: a GET writes nothing into the workspace."""
    from mimics.interfaces.plots import plot_run

    folder = run_folder(request.app.state.workspace, path)
    with tempfile.TemporaryDirectory(prefix="mimics-plot-") as scratch:
        image = plot_run(folder, Path(scratch) / "trajectories.png").read_bytes()
    return Response(image, media_type="image/png")
