"""`mimics run` on a fresh install: the kernels are compiled ahead, in parallel, before the
timed run; the ray part's process is waited for by a run that scans and stopped otherwise.
A step that never returns ends at --wall-limit, naming its line, with nothing left running."""

import contextlib
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from typer.testing import CliRunner

import mimics
from mimics.engine.compiling import warm_up
from mimics.interfaces.cli import kernel_cache
from mimics.interfaces.cli import program as cli
from mimics.interfaces.cli.compiling import first_run
from tests.processes import alive_with, left_running, marked_environment

runner = CliRunner()


@pytest.fixture
def fresh_install(monkeypatch) -> list:
    """Every part looks missing from the cache; returns the compile processes started.

    The processes really run (and find this process's kernels in the cache)."""
    started: list = []
    start = first_run.start_compile

    def spy(part):
        started.append(start(part))
        return started[-1]

    monkeypatch.setattr(warm_up, "missing_parts", lambda: list(warm_up.PARTS))
    monkeypatch.setattr(kernel_cache, "missing_parts", lambda: list(warm_up.PARTS))
    monkeypatch.setattr(first_run, "start_compile", spy)
    return started


def compiled_part(process) -> str:
    """The part a compile process was started for."""
    return process.part


def test_first_run_compiles_ahead_and_stops_the_unneeded_ray_part(tmp_path, fresh_install,
                                                                  monkeypatch):
    helpers = []
    monkeypatch.setattr(warm_up, "compile_ray_helpers", lambda: helpers.append(True))
    out = tmp_path / "run"
    result = runner.invoke(cli.app, ["run", "line", "go_to_goal", "--robots", "2", "--time",
                                     "0.5", "--out", str(out)])
    assert result.exit_code == 0, result.output
    assert "compiling the simulation kernels" in result.output
    assert "finishing the ray kernel" not in result.output  # go_to_goal reads no scan
    # the still part waits for the ray part, which this run never needed
    assert [compiled_part(p) for p in fresh_install] == ["motion", "ray"]
    assert all(p.returncode is not None for p in fresh_install)  # none left running
    assert json.loads((out / "summary.json").read_text())["robots"] == 2
    assert warm_up._ray_part_elsewhere == []
    assert helpers == []  # nor are the ray kernel's helpers compiled by the run


def test_a_first_run_that_scans_waits_for_the_ray_part(tmp_path, fresh_install):
    out = tmp_path / "run"
    result = runner.invoke(cli.app, ["run", "obstacle_room", "dispersion", "--robots", "4",
                                     "--time", "0.5", "--out", str(out)])
    assert result.exit_code == 0, result.output
    (ray,) = [p for p in fresh_install if compiled_part(p) == "ray"]
    assert ray.returncode == 0  # it finished its compile: the run waited for it
    # the still part starts once the ray part is done, not with the others
    assert [compiled_part(p) for p in fresh_install] == ["motion", "ray", "still"]
    assert json.loads((out / "summary.json").read_text())["robots"] == 4


def test_the_run_sets_up_numbas_compiler_for_the_forks_only_when_it_compiles_too(
        tmp_path, fresh_install, monkeypatch):
    """With the index part cached the run compiles nothing before its first scan: setting
    up Numba's compile machinery for the forks would cost every such run 0.2 to 0.3 s."""
    ready: list[bool] = []
    monkeypatch.setattr(warm_up, "ready_to_compile", lambda: ready.append(True))
    monkeypatch.setattr(first_run, "can_fork", lambda: True)
    for missing, expected in ((["ray", "still"], []), (list(warm_up.PARTS), [True])):
        monkeypatch.setattr(warm_up, "missing_parts", lambda m=missing: list(m))
        monkeypatch.setattr(kernel_cache, "missing_parts", lambda m=missing: list(m))
        ready.clear()
        result = runner.invoke(cli.app, ["run", "line", "go_to_goal", "--robots", "2",
                                         "--time", "0.5", "--out", str(tmp_path / "run")])
        assert result.exit_code == 0, result.output
        assert ready == expected, missing


@pytest.mark.parametrize("forks", [True, False])
def test_compiles_started_before_a_bad_option_is_found_are_stopped(tmp_path, fresh_install,
                                                                   monkeypatch, forks):
    """Spawned compiles start before the command's checks and are stopped by a bad option;
    forks of the run would start after them, so none starts."""
    monkeypatch.setattr(first_run, "can_fork", lambda: forks)
    result = runner.invoke(cli.app, ["run", "line", "go_to_goal", "--view", "sometimes",
                                     "--out", str(tmp_path / "run")])
    assert result.exit_code == 2, result.output
    assert "--view: expected one of" in result.output
    started = ["motion", "ray"] if not forks else []
    assert [compiled_part(p) for p in fresh_install] == started
    assert all(p.returncode is not None for p in fresh_install)  # and stopped
    assert first_run._started == []


def test_a_killed_run_leaves_no_compile_process(tmp_path):
    """With an empty cache the run starts its compile processes (forks of itself);
    killing the run (SIGKILL: no handler of its own runs) ends them too."""
    env, marker = marked_environment()
    env["NUMBA_CACHE_DIR"] = str(tmp_path / "empty-cache")
    run = subprocess.Popen([sys.executable, "-m", "mimics", "run", "line", "go_to_goal",
                            "--robots", "2", "--out", "run"], cwd=tmp_path, env=env,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 120
        while (len(compiling(marker, run.pid)) < 2
               and time.monotonic() < deadline and run.poll() is None):
            time.sleep(0.05)
        assert sorted(compiling(marker, run.pid)) == ["mimics-motion", "mimics-ray"]
    finally:
        run.kill()
        run.wait()
    assert left_running(marker) == []


def compiling(marker: str, run: int) -> list[str]:
    """The names (``ps``'s ``comm``) of the marked processes but ``run``."""
    pids = [int(line.split()[0]) for line in alive_with(marker)]
    names = []
    for pid in pids:
        if pid != run:
            with contextlib.suppress(OSError):
                names.append(Path(f"/proc/{pid}/comm").read_text().strip())
    return names


@pytest.mark.parametrize("form", ["_Forked", "_spawn"])
def test_a_compile_process_ends_at_once_with_its_part_in_the_cache(tmp_path, form):
    """A compile process, a fork of the run or a fresh interpreter, ends without Python's
    teardown (os._exit): what it compiled must be on disk by then, so that the run finds
    the part in Numba's cache."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    script = ("from mimics.engine.compiling import warm_up\n"
              "from mimics.interfaces.cli.compiling import processes as compile_processes\n"
              "before = warm_up.missing_parts()\n"
              f"process = compile_processes.{form}('motion')\n"
              "print(process.wait(), process.part, ' '.join(before))\n"
              "print(' '.join(warm_up.missing_parts()))\n")
    done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True,
                          text=True, timeout=300, check=False)
    assert done.returncode == 0, done.stderr
    first, after = done.stdout.splitlines()
    code, part, *before = first.split()
    assert (code, part) == ("0", "motion")
    assert "motion" in before  # an empty cache
    assert after.split() == [p for p in before if p != "motion"]


def test_warm_cache_says_nothing_about_compiling(tmp_path, monkeypatch):
    monkeypatch.setattr(warm_up, "missing_parts", lambda: [])
    monkeypatch.setattr(kernel_cache, "missing_parts", lambda: [])
    result = runner.invoke(cli.app, ["run", "line", "go_to_goal", "--robots", "2", "--time",
                                     "0.5", "--out", str(tmp_path / "run")])
    assert result.exit_code == 0, result.output
    assert "compiling" not in result.output


def test_a_step_that_never_returns_ends_at_the_wall_limit_with_its_line(tmp_path: Path) -> None:
    (tmp_path / "stuck.py").write_text("def step(robot):\n    x, y, theta = robot.pose\n"
                                       "    while x > -1:\n        y = y + 1\n"
                                       "    return 0.5, 0.0\n")
    env, marker = marked_environment()
    done = subprocess.run([sys.executable, "-m", "mimics", "run", "line", "stuck.py",
                           "--robots", "2", "--wall-limit", "1", "--out", "run"],
                          cwd=tmp_path, capture_output=True, text=True, env=env, timeout=300,
                          check=False)
    assert done.returncode == 1, done.stderr
    assert ("\nerror: robot 0: step() did not return within the wall limit of 1 s; stopped at "
            "step 0 (t=0 s), stuck.py:") in done.stdout
    assert done.stdout.split("stuck.py:")[1].startswith(("3\n    while x > -1:\n",
                                                         "4\n    y = y + 1\n"))
    assert "Traceback" not in done.stdout + done.stderr
    assert left_running(marker) == []
    run = mimics.load_run(tmp_path / "run")
    assert run.complete and run.summary["status"] == "wall_limit"
    assert run.summary["exceptions"] == 1 and len(run.trajectory) == 2  # the start, recorded
