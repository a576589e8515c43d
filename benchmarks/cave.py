"""Stage's Cave: 100 Pioneer2DX (LMS200, 180 beams, 8 m), ``deployment`` and ``deployment_team``.

    python benchmarks/cave.py [--time 60] [--repeats 3] [--no-logging] [--threads N] [--quick]

Targets (issue: 2 cores, no live view, logging on, collisions on): per-robot
``deployment`` >= 20 s_sim/s, team ``deployment_team`` >= 100 s_sim/s. Each
form runs in a fresh process (its own peak RSS): one short warm-up run, then
the median of ``--repeats`` runs of ``--time`` simulated seconds, each
recorded like ``mimics run`` into a temporary run folder (unless
``--no-logging``). Prints one row per form and merges them into
benchmarks/results.json under ``cave``.
"""

from __future__ import annotations

from common import deployment_benchmark

TARGETS = {"per-robot": 20.0, "team": 100.0}  # s_sim/s

if __name__ == "__main__":
    deployment_benchmark(__file__, "cave", "100 Pioneer2DX", TARGETS, time=60.0, quick_time=5.0,
                         doc=__doc__)
