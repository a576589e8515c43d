"""Algorithms the workbench may run: the built-in ones and ``.py`` files of the workspace.

Code never arrives in a request to be run: a run or a battery names an
algorithm, and the name must be a built-in or a file under ``algorithms/``.
Uploading an algorithm file is refused unless the server was started with
``--allow-uploads``.
"""

from __future__ import annotations

from pathlib import PurePosixPath
from typing import Any

from fastapi import APIRouter, HTTPException, Request

from mimics.catalog import list_algorithms
from mimics.interfaces.web.security import Workspace

router = APIRouter(prefix="/api/algorithms", tags=["algorithms"])


def algorithm_ref(workspace: Workspace, name: str) -> str:
    """What to hand to ``find_algorithm``: a built-in name, or the real path of a
    workspace file under ``algorithms/``.

    Raises:
        HTTPException: 400 for anything else (an unknown name, a file elsewhere).
    """
    builtin = [n for n, _ in list_algorithms()]
    if name in builtin:
        return name
    if not name.endswith(".py"):
        raise HTTPException(400, f"algorithm {name!r}: expected a built-in ({', '.join(builtin)})"
                                 " or a .py file under algorithms/")
    real = workspace.resolve(name, must_exist=True)
    if workspace.folder("algorithms") not in real.parents or not real.is_file():
        raise HTTPException(400, f"algorithm {name!r}: only files under algorithms/ run")
    return str(real)


@router.get("")
def get_algorithms(request: Request) -> dict[str, Any]:
    """Built-in algorithms (name, description) and the workspace's algorithm files."""
    workspace: Workspace = request.app.state.workspace
    files = sorted(workspace.relative(p) for p in workspace.folder("algorithms").rglob("*.py"))
    return {"builtin": [{"name": n, "description": d} for n, d in list_algorithms()],
            "files": files, "uploads": request.app.state.allow_uploads}


@router.post("/upload")
async def upload_algorithm(request: Request, filename: str) -> dict[str, Any]:
    """Save an uploaded ``.py`` file under ``algorithms/`` (only with ``--allow-uploads``)."""
    if not request.app.state.allow_uploads:
        raise HTTPException(403, "uploading algorithms is off (start `mimics ui "
                                 "--allow-uploads` to allow it)")
    name = PurePosixPath(filename).name
    if name != filename or not name.endswith(".py") or name.startswith("."):
        raise HTTPException(400, f"{filename!r}: expected a plain file name ending in .py")
    workspace: Workspace = request.app.state.workspace
    real = workspace.resolve(f"algorithms/{name}")
    data = await request.body()
    try:
        data.decode("utf-8")
    except UnicodeDecodeError:
        raise HTTPException(400, f"{name}: expected UTF-8 Python source") from None
    real.write_bytes(data)
    return {"path": workspace.relative(real)}
