"""Stage's Hospital: 2,000 robots of 0.1 m (LMS200, 180 beams, 2 m), ``deployment(_team)``.

    python benchmarks/hospital.py [--time 10] [--repeats 3] [--no-logging] [--threads N] [--quick]

Targets (issue 21, the second round: 2 cores, no live view, logging on,
collisions on): per-robot ``deployment`` >= 5 s_sim/s, team
``deployment_team`` >= 20 s_sim/s, each with a peak RSS under 1 GB (the
first round's were 0.5 and 2 s_sim/s). Each
form runs in a fresh process (its own peak RSS): one short warm-up run, then
the median of ``--repeats`` runs of ``--time`` simulated seconds, each
recorded like ``mimics run`` into a temporary run folder (unless
``--no-logging``). Prints one row per form and merges them into
benchmarks/results.json under ``hospital``.
"""

from __future__ import annotations

from common import deployment_benchmark

TARGETS = {"per-robot": 5.0, "team": 20.0}  # s_sim/s (issue 21)
RSS_LIMIT_MB = 1024.0

if __name__ == "__main__":
    deployment_benchmark(__file__, "hospital", "2000 robots", TARGETS, time=10.0, quick_time=0.5,
                         doc=__doc__, rss_limit_mb=RSS_LIMIT_MB)
