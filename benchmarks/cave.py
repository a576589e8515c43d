"""Stage's Cave: 100 Pioneer2DX (LMS200, 180 beams, 8 m), ``deployment`` and ``deployment_team``.

    python benchmarks/cave.py [--time 600] [--repeats 3] [--no-logging] [--threads N] [--quick]

Targets (issue 21, the second round: 2 cores, no live view, logging on,
collisions on): per-robot ``deployment`` >= 80 s_sim/s, team
``deployment_team`` >= 300 s_sim/s (the first round's were 20 and 100). Each
form runs in a fresh process (its own peak RSS): one short warm-up run, then
the median of ``--repeats`` runs of ``--time`` simulated seconds, each
recorded like ``mimics run`` into a temporary run folder (unless
``--no-logging``). Prints one row per form and merges them into
benchmarks/results.json under ``cave``.

The default is the paper's run, 600 simulated seconds (section 5.1: the
figures it gives for its simulator and Stage are of that run). Shorter runs
weigh the end of the run more: writing the 100 per-robot logs and the
Parquet files takes 50 to 120 ms whatever the length, 0.1 ms per step of a
60 s run but 0.01 ms of a 600 s one.
"""

from __future__ import annotations

from common import deployment_benchmark

TARGETS = {"per-robot": 80.0, "team": 300.0}  # s_sim/s (issue 21)

if __name__ == "__main__":
    deployment_benchmark(__file__, "cave", "100 Pioneer2DX", TARGETS, time=600.0, quick_time=5.0,
                         doc=__doc__)
