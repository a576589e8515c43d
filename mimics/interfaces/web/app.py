"""The workbench's app factory: the guards, the four pages' APIs and the static page.

>>> import tempfile
>>> app = create_app(tempfile.mkdtemp())
>>> sorted(p for p in app.openapi()["paths"] if p.startswith("/api/maps"))[:2]
['/api/maps', '/api/maps/file']
"""

from __future__ import annotations

from pathlib import Path

from fastapi import FastAPI, HTTPException, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import FileResponse, JSONResponse
from fastapi.staticfiles import StaticFiles

from mimics.interfaces.web import algorithms, batteries, live, maps, runs, scenarios
from mimics.interfaces.web.jobs import Jobs
from mimics.interfaces.web.live_runs import LiveRuns
from mimics.interfaces.web.security import (
    DEFAULT_BODY_LIMIT,
    DEFAULT_UPLOAD_LIMIT,
    Workspace,
    guard_middleware,
    served_hosts,
)
from mimics.interfaces.web.wording import paths_for_page, validation_for_page
from mimics.world.errors import MimicsError

STATIC = Path(__file__).parent / "static"


def create_app(workspace: str | Path, *, allow_uploads: bool = False, host: str = "127.0.0.1",
               port: int = 8765, hosts: set[str] | None = None,
               body_limit: int = DEFAULT_BODY_LIMIT, upload_limit: int = DEFAULT_UPLOAD_LIMIT,
               battery_workers: int = 1) -> FastAPI:
    """The workbench application serving ``workspace``.

    Args:
        workspace: the folder whose ``maps/``, ``scenarios/``, ``algorithms/``,
            ``batteries/`` and ``runs/`` the page edits (created when missing).
        allow_uploads: accept algorithm files uploaded from the page.
        host: the address served (for the Host/Origin check).
        port: the port served (for the Host/Origin check).
        hosts: the ``host:port`` values accepted instead of those of ``host`` and ``port``.
        body_limit: bytes allowed in a JSON request body.
        upload_limit: bytes allowed in an uploaded map or algorithm file.
        battery_workers: worker processes of each battery started from the page.
    """
    app = FastAPI(title="mimics workbench", version="1",
                  description="The JSON API of `mimics ui`: maps, scenarios, batteries, runs, live "
                              "runs (their frames over the WebSocket /api/live/{id}/stream). "
                              "Paths are relative to the workspace.")
    app.state.workspace = Workspace(workspace)
    app.state.allow_uploads = allow_uploads
    app.state.upload_limit = upload_limit
    app.state.battery_workers = battery_workers
    app.state.jobs = Jobs()
    app.state.live = LiveRuns()  # live runs, each in a worker process (web/live.py)
    app.state.served_hosts = hosts or served_hosts(host, port)
    app.router.on_shutdown.append(app.state.live.close)  # their folders end complete
    app.middleware("http")(guard_middleware(app.state.served_hosts, body_limit, upload_limit))

    @app.exception_handler(MimicsError)
    async def bad_input(request: Request, exc: MimicsError) -> JSONResponse:
        return JSONResponse({"detail": paths_for_page(str(exc), app.state.workspace.root)},
                            status_code=422)

    @app.exception_handler(RequestValidationError)
    async def bad_request(request: Request, exc: RequestValidationError) -> JSONResponse:
        # one sentence for the page, not pydantic's list ("List should have at least...")
        return JSONResponse({"detail": validation_for_page(exc.errors())}, status_code=422)

    for module in (maps, scenarios, algorithms, batteries, runs, live):
        app.include_router(module.router)

    @app.get("/api/jobs/{job_id}", tags=["jobs"])
    def job(job_id: int) -> dict[str, object]:
        """A background job (a run, a video export, a battery session) and its progress."""
        found = app.state.jobs.get(job_id)
        if found is None:
            raise HTTPException(404, f"no job {job_id}")
        return found.as_dict()

    @app.get("/", include_in_schema=False)
    def index() -> FileResponse:
        return FileResponse(STATIC / "index.html")

    app.mount("/static", StaticFiles(directory=STATIC), name="static")
    return app
