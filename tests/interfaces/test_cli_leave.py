"""The console script ends the process itself: exit handlers, streams, status and threads kept."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ALGORITHM = '''
import atexit
from pathlib import Path

from mimics.algorithms.go_to_goal import step

atexit.register(lambda: Path({marker!r}).write_text("exit handlers ran"))
'''


def test_a_run_ends_with_its_exit_handlers_run_and_its_output_flushed(tmp_path: Path) -> None:
    marker = tmp_path / "marker.txt"
    algorithm = tmp_path / "leaving.py"
    algorithm.write_text(ALGORITHM.format(marker=str(marker)))
    done = subprocess.run([sys.executable, "-m", "mimics", "run", "line", str(algorithm),
                           "--robots", "3", "--time", "2", "--out", str(tmp_path / "run")],
                          capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    assert marker.read_text() == "exit handlers ran"
    assert "line / leaving / seed 0" in done.stdout and "records in" in done.stdout
    assert (tmp_path / "run" / "summary.json").exists()


def test_bad_input_still_ends_with_status_2() -> None:
    done = subprocess.run([sys.executable, "-m", "mimics", "run", "no_such_scenario", "go_to_goal"],
                          capture_output=True, text=True, timeout=300, check=False)
    assert done.returncode == 2
    assert "unknown scenario 'no_such_scenario'" in done.stderr


def test_a_thread_still_working_is_waited_for(tmp_path: Path) -> None:
    # leave() cuts nothing short: with a thread of the program's own still running,
    # the process ends the ordinary way, after that thread.
    written = tmp_path / "late.txt"
    script = f"""
import threading, time
from pathlib import Path
from mimics.interfaces.cli.leave import leave

def late():
    time.sleep(0.5)
    Path({str(written)!r}).write_text("done")

threading.Thread(target=late).start()
print("leaving", flush=False)
leave(3)
"""
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=60, check=False)
    assert done.returncode == 3
    assert done.stdout == "leaving\n"
    assert written.read_text() == "done"


def test_without_threads_the_status_and_buffered_output_survive() -> None:
    script = """
import sys
from mimics.interfaces.cli.leave import leave
sys.stdout.write("buffered, never flushed by hand")
leave(5)
"""
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True,
                          timeout=60, check=False)
    assert (done.returncode, done.stdout) == (5, "buffered, never flushed by hand")
