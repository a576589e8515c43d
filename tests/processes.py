"""Finding processes a test started that are still alive (with ``ps``)."""

from __future__ import annotations

import os
import subprocess
import time
import uuid

from tests.system_packages import require


def marked_environment() -> tuple[dict[str, str], str]:
    """A copy of the environment with a marker of its own, inherited by every child process."""
    marker = uuid.uuid4().hex
    return {**os.environ, "MIMICS_TEST_MARKER": marker}, marker


def alive_with(marker: str) -> list[str]:
    """``pid command`` of the processes whose environment holds ``marker`` (ps's ``e``)."""
    require("ps")
    listing = subprocess.run(["ps", "-e", "e", "-ww", "-o", "pid=,args="], capture_output=True,
                             text=True, check=True).stdout
    needle = f"MIMICS_TEST_MARKER={marker}"
    return [line.split(needle)[0].strip() for line in listing.splitlines()
            if needle in line and int(line.split()[0]) != os.getpid()]


def left_running(marker: str, grace: float = 10.0) -> list[str]:
    """The processes with ``marker`` still alive after ``grace`` seconds (processes that
    are ending, such as a fork server whose parent just exited, get that long)."""
    end = time.monotonic() + grace
    while True:
        alive = alive_with(marker)
        if not alive or time.monotonic() >= end:
            return alive
        time.sleep(0.1)
