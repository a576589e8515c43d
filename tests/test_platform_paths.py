"""The process paths of Windows and macOS, run on Linux by forcing the one switch they read
(:mod:`mimics.process_platform`): workers started by ``spawn``, no ``PR_SET_PDEATHSIG``, no
forked compile processes, and the watcher thread as the only guard against leftover
workers (issue 54: everything was tested on Linux's paths only)."""

from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
import time
from pathlib import Path

import pytest

from mimics.process_platform import (
    PLATFORM_ENV,
    has_death_signal,
    process_platform,
    worker_start_method,
)
from mimics.world.errors import MimicsError

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"),
                                reason="forces the other systems' paths from Linux's")

# what a process decides, asked of a fresh interpreter; PR_GET_PDEATHSIG is the kernel's
# own record of the death signal the worker set
PROBE = """
import ctypes, json, shutil
from mimics.batteries.workers import _die_with_parent_signal, worker_context
from mimics.interfaces.child_processes import dying_with_parent
from mimics.interfaces.cli.compiling.processes import can_fork
_die_with_parent_signal()
found = ctypes.c_int(0)
ctypes.CDLL(None, use_errno=True).prctl(2, ctypes.byref(found))  # PR_GET_PDEATHSIG
print(json.dumps({"death_signal": found.value, "start": worker_context().get_start_method(),
                  "fork_compiles": can_fork(), "command": dying_with_parent(["x"])}))
"""

BATTERY = """[battery]
name = "platform"
algorithms = ["{algorithm}"]
seeds = 2
time = {time}
timeout = 60

[[scenarios]]
name = "line"
robots = 2
"""

ENDLESS = """def step(robot):
    while True:
        pass
"""


def environment(platform: str | None) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != PLATFORM_ENV}
    return {**env, PLATFORM_ENV: platform} if platform else env


def probe(platform: str | None) -> dict[str, object]:
    done = subprocess.run([sys.executable, "-c", PROBE], env=environment(platform),
                          capture_output=True, text=True, timeout=120, check=True)
    return json.loads(done.stdout.splitlines()[-1])


def test_the_switch_reads_the_system_unless_forced(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(PLATFORM_ENV, raising=False)
    assert (process_platform(), has_death_signal(), worker_start_method()) == (
        "linux", True, "forkserver")
    monkeypatch.setenv(PLATFORM_ENV, "macos")
    assert (process_platform(), has_death_signal(), worker_start_method()) == (
        "macos", False, "forkserver")
    monkeypatch.setenv(PLATFORM_ENV, "windows")
    assert (process_platform(), has_death_signal(), worker_start_method()) == (
        "windows", False, "spawn")
    monkeypatch.setenv(PLATFORM_ENV, "linux")  # forcing Linux's paths elsewhere would break
    with pytest.raises(MimicsError, match=f"{PLATFORM_ENV}: expected one of macos, windows"):
        process_platform()


@pytest.mark.parametrize(("platform", "start"), [("windows", "spawn"), ("macos", "forkserver")])
def test_the_forced_paths_reach_the_processes_that_take_them(platform: str, start: str) -> None:
    linux = probe(None)
    assert linux["death_signal"] == signal.SIGKILL and linux["start"] == "forkserver"
    assert linux["fork_compiles"] is True
    other = probe(platform)
    assert other == {"death_signal": 0, "start": start, "fork_compiles": False,
                     "command": ["x"]}  # no setpriv --pdeathsig either


def done_runs(db: Path) -> int:
    if not db.is_file():
        return 0
    with sqlite3.connect(db) as connection:
        try:
            return connection.execute("SELECT COUNT(*) FROM runs WHERE state = 'done'"
                                      ).fetchone()[0]
        except sqlite3.OperationalError:
            return 0


def test_a_two_worker_battery_on_spawned_workers(tmp_path: Path) -> None:
    (tmp_path / "battery.toml").write_text(BATTERY.format(algorithm="go_to_goal", time=2.0))
    done = subprocess.run([sys.executable, "-m", "mimics", "battery", "run", "battery.toml",
                           "--out", "b", "--workers", "2", "--no-progress"], cwd=tmp_path,
                          env=environment("windows"), capture_output=True, text=True,
                          timeout=300, check=False)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done_runs(tmp_path / "b" / "battery.db") == 2
    assert sorted(p.name for p in (tmp_path / "b" / "workers").glob("*.log")) == [
        "w1.log", "w2.log"]


def children(pid: int) -> list[int]:
    """Processes whose parent is ``pid``."""
    found = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            found.append(int(stat.parent.name))
    return found


def alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def test_spawned_workers_end_with_a_killed_battery_without_a_death_signal(
        tmp_path: Path) -> None:
    """Without PR_SET_PDEATHSIG the workers' watcher thread is all that ends them."""
    (tmp_path / "endless.py").write_text(ENDLESS)
    (tmp_path / "battery.toml").write_text(BATTERY.format(algorithm="endless.py", time=5.0))
    battery = subprocess.Popen([sys.executable, "-m", "mimics", "battery", "run",
                                "battery.toml", "--out", "b", "--workers", "2",
                                "--no-progress"], cwd=tmp_path, env=environment("windows"),
                               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    workers: list[int] = []
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and battery.poll() is None:
            workers = [pid for pid in children(battery.pid)
                       if b"spawn_main" in Path(f"/proc/{pid}/cmdline").read_bytes()]
            logs = list((tmp_path / "b" / "workers").glob("*.log"))
            if len(workers) == 2 and all("--- mimics battery: run" in p.read_text()
                                         for p in logs) and len(logs) == 2:
                break  # both workers inside the endless step
            time.sleep(0.2)
        assert len(workers) == 2, "the battery did not start two spawned workers"
    finally:
        battery.kill()  # SIGKILL: nothing of the battery's own runs any more
        battery.wait()
    deadline = time.monotonic() + 15
    while time.monotonic() < deadline and any(alive(pid) for pid in workers):
        time.sleep(0.2)
    left = [pid for pid in workers if alive(pid)]
    for pid in left:  # do not leave them behind, whatever the outcome
        os.kill(pid, signal.SIGKILL)
    assert not left, "spawned workers outlived their battery"


def test_a_wall_limit_run_on_the_forced_paths_stops_an_endless_step(tmp_path: Path) -> None:
    (tmp_path / "endless.py").write_text(ENDLESS)
    done = subprocess.run([sys.executable, "-m", "mimics", "run", "line", "endless.py",
                           "--robots", "2", "--time", "5", "--wall-limit", "2", "--out", "run",
                           "--robot-logs", "off"], cwd=tmp_path, env=environment("windows"),
                          capture_output=True, text=True, timeout=120, check=False)
    said = done.stdout + done.stderr
    assert done.returncode == 1, said[-2000:]
    assert "within the wall limit of 2 s" in said and "endless.py:2" in said, said[-2000:]
