"""Batteries: algorithms x scenarios x seeds (x parameter sweeps), unattended.

Launch in the evening, find in the morning a complete table of results, with
every failure recorded and nothing lost or repeated (SPEC section 8)::

    from mimics.batteries import run_battery, resume_battery, runs_table
    run_battery("battery.toml", "batteries/night1", workers=2)
    resume_battery("batteries/night1")        # after a kill: goes on where it stopped
    runs_table("batteries/night1")            # one row per run (pandas)

Modules: :mod:`~mimics.batteries.spec` (battery files), :mod:`~mimics.batteries.store`
(SQLite state), :mod:`~mimics.batteries.workers` (isolated worker processes),
:mod:`~mimics.batteries.local` and :mod:`~mimics.batteries.dask_backend`
(executors), :mod:`~mimics.batteries.driver` (the loop),
:mod:`~mimics.batteries.report` (the top-tier table), :mod:`~mimics.batteries.status`,
:mod:`~mimics.batteries.metrics` (per-run metrics and digests),
:mod:`~mimics.batteries.stats` (intervals, paired differences, signed-rank tests),
:mod:`~mimics.batteries.comparison` (their tables), :mod:`~mimics.batteries.until` and
:mod:`~mimics.batteries.rounds` (batteries that stop when the answer is known).
"""

from __future__ import annotations

import importlib
from typing import Any

_EXPORTS = {
    "BatterySpec": "mimics.batteries.spec",
    "load_battery": "mimics.batteries.spec",
    "spec_from_dict": "mimics.batteries.spec",
    "run_battery": "mimics.batteries.driver",
    "resume_battery": "mimics.batteries.driver",
    "rerun_failed": "mimics.batteries.driver",
    "BatteryResult": "mimics.batteries.driver",
    "battery_status": "mimics.batteries.status",
    "runs_table": "mimics.batteries.report",
    "aggregate": "mimics.batteries.report",
    "export_table": "mimics.batteries.report",
}

__all__ = list(_EXPORTS)


def __getattr__(name: str) -> Any:
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'mimics.batteries' has no attribute {name!r}")
