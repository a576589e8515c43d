"""``[battery] sandbox = "bwrap"``: each run under bubblewrap (issue 54, item 2).

A private working folder keeps a submission's relative paths from its classmates'
files, not its absolute ones. The snooping submission below tries, at import, to
read a classmate's file by its absolute path, to list the submissions' folder and
to write into the battery folder, and to read the battery's environment, and
reports what it saw in its run's error.
Without the sandbox it succeeds (the documented hole); in the sandbox it sees an
empty, read-only folder. The honest submission's runs are the same, bit for bit,
in and out of the sandbox (their digests), and a step that never returns is still
a time-out, with the stack it was stuck in.
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import pytest

from mimics.batteries import run_battery, runs_table
from mimics.interfaces.cli import main
from tests.batteries.helpers import fault, write_battery
from tests.system_packages import require

HONEST = '''import math

def step(robot):
    x, y, _ = robot.pose
    gx, gy = robot.goal
    return 1.0, math.atan2(gy - y, gx - x)
'''
SNOOP = '''import os

def attempt(action):
    try:
        return repr(action())
    except OSError as exc:
        return type(exc).__name__

seen = attempt(lambda: open({classmate!r}).read()[:11])
listed = attempt(lambda: sorted(os.listdir({folder!r})))
wrote = attempt(lambda: open({planted!r}, "w").write("x"))
token = os.environ.get("TEACHER_TOKEN")
raise RuntimeError(f"seen={{seen}} listed={{listed}} wrote={{wrote}} token={{token}}")
'''


def _battery(tmp_path: Path, sandbox: str) -> tuple[Path, Path]:
    submissions = tmp_path / "submissions"
    submissions.mkdir(exist_ok=True)
    alice, bob = submissions / "alice.py", submissions / "bob.py"
    alice.write_text(HONEST)
    out = tmp_path / f"graded-{sandbox}"
    bob.write_text(SNOOP.format(classmate=str(alice), folder=str(submissions),
                                planted=str(out / "planted.txt")))
    path = write_battery(tmp_path / f"{sandbox}.toml", [str(alice), str(bob),
                                                        fault("sleep_forever")],
                         seeds=2, time=2.0, timeout=2.0, isolation="run", sandbox=sandbox)
    return path, out


def test_the_sandbox_hides_classmates_and_the_battery_folder(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    require("bubblewrap")
    monkeypatch.setenv("TEACHER_TOKEN", "s3cret")  # the battery's environment
    runs = {}
    for sandbox in ("none", "bwrap"):
        path, out = _battery(tmp_path, sandbox)
        run_battery(path, out, workers=2, progress=False)
        runs[sandbox] = runs_table(out).set_index(["algorithm", "seed"])
        states = runs[sandbox]["state"].to_dict()
        assert states == {("alice", 1): "done", ("alice", 2): "done", ("bob", 1): "error",
                          ("bob", 2): "error", ("sleep_forever", 1): "timeout",
                          ("sleep_forever", 2): "timeout"}, sandbox
        # a step stuck in C is killed at the hard deadline, its stack dumped first
        assert "sleep_forever.py\", line 7 in step" in \
            runs[sandbox].loc[("sleep_forever", 1), "traceback"]
        error = runs[sandbox].loc[("bob", 1), "error"]
        if sandbox == "none":  # the hole the sandbox closes
            assert "seen='import math'" in error and "'alice.py', 'bob.py'" in error
            assert "wrote=1" in error and (out / "planted.txt").exists()
        else:
            assert "seen=FileNotFoundError" in error and "listed=[]" in error, error
            assert "wrote=OSError" in error and not (out / "planted.txt").exists(), error
            assert "token=None" in error  # only the variables a run needs go in
    assert runs["bwrap"]["worker"].str.contains("bwrap pid").all()
    assert runs["bwrap"]["worker"].nunique() == 6  # a sandbox per run
    # the honest runs are bit for bit the same in the sandbox
    assert runs["bwrap"].loc["alice", "digest"].tolist() == \
        runs["none"].loc["alice", "digest"].tolist()
    assert runs["bwrap"].loc["alice", "digest"].notna().all()


@pytest.mark.parametrize(("battery", "args", "named"), [
    ({"isolation": "run"}, ["--sandbox", "bwrap"], "--sandbox bwrap"),
    ({"sandbox": "bwrap"}, [], "sandbox = \"bwrap\""),
])
def test_a_sandbox_without_bwrap_is_one_error_and_nothing_started(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, battery: dict[str, str],
        args: list[str], named: str) -> None:
    path = write_battery(tmp_path / "b.toml", ["go_to_goal"], **battery)
    empty = tmp_path / "no-bwrap-here"
    empty.mkdir()
    monkeypatch.setenv("PATH", str(empty))
    stderr = io.StringIO()
    with contextlib.redirect_stderr(stderr):
        status = main(["battery", "run", str(path), "--out", str(tmp_path / "out"), *args])
    error = stderr.getvalue()
    assert status == 2, error
    assert named in error and "apt-get install bubblewrap" in error, error
    assert len(error.strip().splitlines()) == 1 and "Traceback" not in error
    assert not (tmp_path / "out").exists()
