"""The workbench's guards: paths stay inside the workspace, state changes come from the page.

A local web server is reachable by every site the user's browser opens, and a
DNS-rebinding attack can make a foreign name point at 127.0.0.1. So:

* every path the API takes is relative to the workspace and resolved there:
  an absolute path or ``..`` is refused with 400, a path whose real location
  (after symlinks) is outside the workspace with 403, and nothing is read;
* every request whose ``Host`` is not the one served is refused with 403 (a
  rebound name is not served, not even for reading), and a request that
  changes state (POST, PUT, PATCH, DELETE) also when its ``Origin`` (when
  sent) is another host: a foreign page cannot post here;
* request bodies are limited in size (413);
* a WebSocket (the live stream) is refused on the same terms: its ``Host`` must
  be served and its ``Origin``, which browsers always send, must be this server
  (:func:`websocket_refusal`), since a foreign page may open a WebSocket to any
  address and the HTTP middleware does not see WebSocket requests.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from pathlib import Path, PurePosixPath
from typing import Any
from urllib.parse import urlsplit

from fastapi import HTTPException, Request, Response
from fastapi.responses import JSONResponse

WORKSPACE_FOLDERS = ("maps", "scenarios", "algorithms", "batteries", "runs")
STATE_CHANGING = frozenset({"POST", "PUT", "PATCH", "DELETE"})
DEFAULT_BODY_LIMIT = 2_000_000  # bytes of JSON (a Hospital-sized map is about 1 MB)
DEFAULT_UPLOAD_LIMIT = 20_000_000  # bytes of an imported image or drawing
LOOPBACK_NAMES = ("127.0.0.1", "localhost", "::1", "[::1]")


class Workspace:
    """The folder the workbench serves: ``maps/``, ``scenarios/``, ``algorithms/``,
    ``batteries/``, ``runs/`` (created when missing).

    Args:
        root: the workspace folder.
    """

    def __init__(self, root: str | Path) -> None:
        self.root = Path(root).expanduser().resolve()
        for name in WORKSPACE_FOLDERS:
            (self.root / name).mkdir(parents=True, exist_ok=True)

    def folder(self, name: str) -> Path:
        """One of the workspace's folders."""
        return self.root / name

    def resolve(self, relative: str, *, must_exist: bool = False) -> Path:
        """The real path of ``relative`` (a workspace-relative path), checked to stay inside.

        Raises:
            HTTPException: 400 for an empty or absolute path or one with ``..``;
                403 when it resolves (through a symlink) outside the workspace;
                404 when ``must_exist`` and it does not exist.
        """
        text = (relative or "").replace("\\", "/")
        pure = PurePosixPath(text)
        if not text.strip() or text.startswith("/") or pure.is_absolute() or (
                len(text) > 1 and text[1] == ":"):
            raise HTTPException(400, f"path {relative!r}: expected a path relative to the "
                                     "workspace")
        if ".." in pure.parts or "\x00" in text:
            raise HTTPException(400, f"path {relative!r}: '..' is not allowed")
        try:
            real = (self.root / pure).resolve()
            exists = real.exists()
        except (OSError, ValueError) as exc:  # a name too long, a loop of symlinks...
            raise HTTPException(400, f"path {relative[:100]!r}: not a usable path "
                                     f"({exc.__class__.__name__}: {exc.args[-1]})") from None
        if real != self.root and self.root not in real.parents:
            raise HTTPException(403, f"path {relative!r}: leads outside the workspace")
        if must_exist and not exists:
            raise HTTPException(404, f"path {relative!r}: no such file or folder")
        return real

    def relative(self, path: Path) -> str:
        """``path`` (inside the workspace) as the workspace-relative text the API uses."""
        return path.resolve().relative_to(self.root).as_posix()


def _host_of(value: str) -> str:
    """``host:port`` of a Host header or an Origin URL, lower-cased."""
    if "://" in value:
        value = urlsplit(value).netloc
    return value.strip().lower()


def guard_middleware(served_hosts: set[str], body_limit: int, upload_limit: int
                     ) -> Callable[[Request, Callable[[Request], Awaitable[Response]]],
                                   Awaitable[Response]]:
    """An HTTP middleware refusing foreign hosts, foreign state changes and oversized bodies.

    Args:
        served_hosts: ``host:port`` values this server answers to (the Host header).
        body_limit: bytes allowed in a JSON request body.
        upload_limit: bytes allowed in an upload (paths under ``/api/*/import`` or
            ``/api/algorithms/upload``).
    """

    async def guard(request: Request, call_next: Callable[[Request], Awaitable[Response]]
                    ) -> Response:
        host = _host_of(request.headers.get("host", ""))
        if host not in served_hosts:  # a rebound name must not even read the workspace
            return JSONResponse({"detail": f"refused: Host {host!r} is not this server"},
                                status_code=403)
        if request.method in STATE_CHANGING:
            origin = request.headers.get("origin")
            if origin is not None and _host_of(origin) not in served_hosts:
                return JSONResponse({"detail": f"refused: Origin {origin!r} is not this "
                                               "server"}, status_code=403)
            limit = upload_limit if request.url.path.endswith(("/import", "/upload")) \
                else body_limit
            length = request.headers.get("content-length")
            if length is not None and (not length.isdigit() or int(length) > limit):
                return JSONResponse({"detail": f"request body too large (limit {limit} "
                                               "bytes)"}, status_code=413)
            body = await request.body()  # also bounds chunked bodies without a length
            if len(body) > limit:
                return JSONResponse({"detail": f"request body too large (limit {limit} "
                                               "bytes)"}, status_code=413)
        return await call_next(request)

    return guard


def websocket_refusal(headers: Any, served_hosts: set[str]) -> str | None:
    """Why a WebSocket handshake with ``headers`` is refused, or None when it is not: a
    Host not served, or an Origin that is another host (a page of another site)."""
    host = _host_of(headers.get("host", ""))
    if host not in served_hosts:
        return f"refused: Host {host!r} is not this server"
    origin = headers.get("origin")
    if origin is not None and _host_of(origin) not in served_hosts:
        return f"refused: Origin {origin!r} is not this server"
    return None


def served_hosts(host: str, port: int) -> set[str]:
    """The Host header values a server on ``host:port`` accepts (loopback names are one)."""
    names = set(LOOPBACK_NAMES) if host in LOOPBACK_NAMES or host == "0.0.0.0" else set()
    names.add(host.lower())
    hosts = {f"{name}:{port}" for name in names}
    if port == 80:
        hosts |= names
    return hosts
