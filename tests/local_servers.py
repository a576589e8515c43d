"""Servers the tests start on loopback: a folder over HTTP (the Stage repository's
layout, for downloads) and stopping a server process they launched."""

from __future__ import annotations

import contextlib
import functools
import http.server
import shutil
import subprocess
import threading
from collections.abc import Iterator
from pathlib import Path
from typing import ClassVar

from mimics.world.stage_data import STAGE_FILES
from tests.stage import stage_file


def stage_repository(root: Path) -> Path:
    """Copy the shared Stage files into ``root`` at their paths in the repository."""
    source = stage_file("cave.world").parent
    for name, spec in STAGE_FILES.items():
        target = root / spec.remote
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(source / name, target)
    return root


class QuietHandler(http.server.SimpleHTTPRequestHandler):
    """Serves files without a request log on stderr; keeps the paths asked for instead."""

    requests: ClassVar[list[str]] = []  # to count downloads

    def log_message(self, format: str, *args: object) -> None:
        QuietHandler.requests.append(self.path)


@contextlib.contextmanager
def serve(root: Path) -> Iterator[str]:
    """An HTTP server on 127.0.0.1 serving ``root``; yields its base URL."""
    handler = functools.partial(QuietHandler, directory=str(root))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


def stop_process(process: subprocess.Popen[bytes], grace: float) -> None:
    """SIGTERM ``process``, and SIGKILL it if it has not ended ``grace`` seconds later."""
    process.terminate()
    try:
        process.wait(grace)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait()
