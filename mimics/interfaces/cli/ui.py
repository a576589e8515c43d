"""``mimics ui``: the workbench in the browser (maps, scenarios, batteries, runs)."""

from __future__ import annotations

import threading
import webbrowser
from pathlib import Path
from typing import Annotated

import typer

from mimics.interfaces.cli.output import fail, note

LOOPBACK = ("127.0.0.1", "localhost", "::1")


def ui_command(
    workspace: Annotated[Path, typer.Option(help="The workspace folder (maps/, scenarios/, "
                                                 "algorithms/, batteries/, runs/).")]
    = Path("."),
    port: Annotated[int, typer.Option(help="The port to serve on.")] = 8765,
    host: Annotated[str, typer.Option(help="The address to bind (anything but loopback "
                                           "exposes the workspace to the network).")]
    = "127.0.0.1",
    open_browser: Annotated[bool, typer.Option("--open", help="Open the page in the browser."
                                               )] = False,
    allow_uploads: Annotated[bool, typer.Option(help="Accept algorithm files uploaded from "
                                                     "the page.")] = False,
) -> None:
    """Serve the workbench: draw maps, place robots, run batteries and replay runs."""
    try:
        import uvicorn

        from mimics.interfaces.web.app import create_app
    except ImportError as exc:
        raise fail(f"mimics ui needs the 'ui' extra: pip install 'mimics-sim[ui]' "
                   f"({exc})") from None
    if not 0 < port < 65536:
        raise fail(f"--port: expected 1..65535, got {port}")
    if workspace.exists() and not workspace.is_dir():
        raise fail(f"--workspace {workspace}: not a folder")
    if host not in LOOPBACK:
        note(f"mimics: warning: serving on {host}: anyone who can reach this address can "
             "edit the workspace and run its algorithms")
    app = create_app(workspace, allow_uploads=allow_uploads, host=host, port=port)
    url = f"http://{'[' + host + ']' if ':' in host else host}:{port}/"
    note(f"mimics: workbench on {url} (workspace {workspace.resolve()}); Ctrl-C stops it")
    if open_browser:
        threading.Timer(1.0, webbrowser.open, args=(url,)).start()
    uvicorn.run(app, host=host, port=port, log_level="warning")
