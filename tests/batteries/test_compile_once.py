"""A fresh install's first battery compiles each kernel part once, not once per worker.

Numba itself tells who compiled what: with ``NUMBA_DEBUG_CACHE=1`` every kernel it
compiles and saves to its cache prints ``[cache] data saved to PATH`` on the
process's output, which for the battery's processes is a log in ``workers/``.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

from mimics.batteries import compile_once
from mimics.engine.compiling import warm_up
from tests.batteries.helpers import write_battery

SAVED = re.compile(r"\[cache\] data saved to '([^']+)'")


def saved_files(log: Path) -> list[str]:
    """The cache files (``module.kernel-LINE.pyXY.N.nbc``) a process's log says it saved."""
    return [Path(path).name for path in SAVED.findall(log.read_text())]


def test_a_fresh_install_compiles_each_part_once_for_all_workers(tmp_path: Path) -> None:
    cache = tmp_path / "empty-numba-cache"  # a fresh install, for the battery and its children
    cache.mkdir()
    battery = write_battery(tmp_path / "scan.toml", ["wall_aware"], seeds=4, time=1.0,
                            timeout=300.0, scenarios=[{"name": "circle_swap", "robots": 4}])
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "NUMBA_DEBUG_CACHE": "1"}
    out = tmp_path / "out"
    done = subprocess.run([sys.executable, "-m", "mimics", "battery", "run", str(battery),
                           "--workers", "2", "--out", str(out), "--no-progress"],
                          cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300,
                          check=False)
    assert done.returncode == 0, done.stderr

    summaries = sorted((out / "runs").glob("*/summary.json"))
    assert len(summaries) == 4
    for summary in summaries:  # each worker's first run compiled ~18 s before the change
        assert json.loads(summary.read_text())["compile_time"] < 0.05, summary.parent.name

    logs = out / "workers"
    workers = sorted(logs.glob("w*.log"))
    assert len(workers) == 2
    for log in workers:  # the workers only loaded kernels from the cache
        assert saved_files(log) == [], log.name
    compiles = {log.name: saved_files(log) for log in logs.glob("compile-*.log")}
    assert sorted(compiles) == sorted(f"compile-{part}.log" for part in warm_up.PARTS)
    for part, kernels in warm_up._WITNESSES.items():  # each part in its own process, once
        for kernel in kernels:
            stem = warm_up._cache_stem(kernel) + "-"
            mine = [name for name in compiles[f"compile-{part}.log"] if name.startswith(stem)]
            assert len(mine) == 1, (part, stem, mine)
    assert compile_once.MESSAGE in done.stderr  # the battery said so, once
    assert done.stderr.count(compile_once.MESSAGE) == 1


def test_a_failed_compile_process_loses_nothing(tmp_path: Path,
                                                monkeypatch: pytest.MonkeyPatch) -> None:
    """A part its process cannot compile (here one that does not exist): the battery
    goes on, its workers compiling what is missing as before."""
    monkeypatch.setattr(warm_up, "missing_parts", lambda: ["no_such_part"])
    assert compile_once.compile_missing_parts(tmp_path / "logs") == []
    assert "KeyError: 'no_such_part'" in (tmp_path / "logs/compile-no_such_part.log").read_text()


def test_a_warm_cache_starts_no_compile_process(tmp_path: Path,
                                                monkeypatch: pytest.MonkeyPatch,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setattr(warm_up, "missing_parts", lambda: [])
    assert compile_once.compile_missing_parts(tmp_path / "logs") == []
    assert not (tmp_path / "logs").exists()
    assert capsys.readouterr().err == ""
