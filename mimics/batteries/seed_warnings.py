"""Cells where two or more seeds gave identical runs, and what made them identical.

A seed draws a run's start poses (where the scenario randomizes them) and its
sensor noise. Seeds that give identical runs (the same digest, see
:func:`mimics.batteries.metrics.run_digest`) are not independent observations:
the warning names the cell, the seeds and the real cause, a parameter that
fixed the starts (``fixed = true``, ``random_yaw = false``, a jitter of 0,
``noise = "off"``) or, where noise was on, an algorithm that read no noisy
sensor.
"""

from __future__ import annotations

from typing import Any

import pandas as pd

from mimics.world.errors import MimicsError

CELL = ["algorithm", "scenario", "parameters"]


def seed_ranges(seeds: list[int]) -> str:
    """``[1, 2, 3, 7]`` -> ``"1-3, 7"``."""
    ordered = sorted(seeds)
    parts: list[str] = []
    start = previous = ordered[0]
    for seed in [*ordered[1:], None]:
        if seed is not None and seed == previous + 1:
            previous = seed
            continue
        parts.append(str(start) if start == previous else f"{start}-{previous}")
        if seed is not None:
            start = previous = seed
    return ", ".join(parts)


def identical_seed_warnings(table: pd.DataFrame, hints: dict[str, str] | None = None
                            ) -> list[str]:
    """One line per cell where two or more seeds gave identical runs (same digest), with
    what made them identical.

    Args:
        table: the per-run table (its ``digest`` column: see
            :func:`mimics.batteries.metrics.run_digest`; ``params`` as JSON).
        hints: scenario name -> what to do instead (default: :func:`randomize_hints`' advice
            and the cell's own cause, see :func:`identical_cause`).
    """
    if table.empty or "digest" not in table.columns:
        return []
    lines = []
    knobs = randomize_knobs(table)
    done = table[(table["state"] == "done") & table["digest"].notna()]
    for (algorithm, scenario, label), group in done.groupby(CELL, sort=False):
        for digest, same in group.groupby("digest", sort=False):
            if len(same) < 2:
                continue
            seeds = [int(s) for s in same["seed"]]
            what = "runs" if str(digest).startswith("t:") else "outcomes"
            cell = f"{algorithm} x {scenario}" + (f" ({label})" if label else "")
            alone = len(same) == len(group)
            params = _params_of(same.iloc[0])
            hint = (hints or {}).get(scenario) or identical_cause(params, knobs.get(scenario, []))
            lines.append(f"seeds {seed_ranges(seeds)} of {cell} gave identical {what}: "
                         + ("the seed changes nothing here" if alone else
                            f"{len(same)} of {len(group)} seeds are copies of one run")
                         + f"; {hint}")
    return lines


def identical_cause(params: dict[str, Any], knobs: list[str]) -> str:
    """Why seeds gave identical runs, from the cell's parameters and the scenario's knobs.

    >>> identical_cause({"fixed": True}, ["jitter", "yaw_jitter", "fixed"])[:50]
    'fixed = true fixed the start poses, and the algorit'
    >>> identical_cause({"fixed": True}, ["fixed"]).split(": ")[-1]
    'set fixed = false to draw the starts from the seed'
    >>> identical_cause({}, [])[:46]
    'the scenario draws no start pose from the seed'
    """
    fixing = [_assignment(name, value) for name, value in params.items()
              if _fixes_starts(name, value)]
    noise_off = str(params.get("noise", "on")).lower() in ("off", "false")
    starts = (f"{' and '.join(fixing)} fixed the start poses" if fixing else
              "the scenario draws no start pose from the seed" if not
              [k for k in knobs if k != "noise"] else "the starts drawn from the seed changed "
              "nothing the algorithm did")
    noise = ('noise = "off" turned the sensor noise off' if noise_off else
             "the algorithm read no noisy sensor (noise is on"
             + (")" if fixing else ": it read only exact values such as true_pose, goal or "
                "comms)"))
    advice = ""
    if fixing:
        first = next(name for name, value in params.items() if _fixes_starts(name, value))
        undo = _assignment(first, _undo(params[first]))
        advice = f": set {undo} to draw the starts from the seed"
    elif noise_off:
        advice = ': leave noise on for runs that differ by seed'
    return f"{starts}, and {noise}{advice}"


def _fixes_starts(name: str, value: Any) -> bool:
    if name == "fixed":
        return value is True
    if name.startswith("random"):
        return value is False
    if "jitter" in name:
        return isinstance(value, int | float) and not isinstance(value, bool) and value == 0
    return False


def _undo(value: Any) -> Any:
    return not value if isinstance(value, bool) else "a value above 0"


def _assignment(name: str, value: Any) -> str:
    shown = str(value).lower() if isinstance(value, bool) else value
    return f"{name} = {shown}"


def _params_of(row: Any) -> dict[str, Any]:
    import json

    text = row.get("params") if hasattr(row, "get") else None
    try:
        params = json.loads(text) if isinstance(text, str) else {}
    except ValueError:
        params = {}
    return params if isinstance(params, dict) else {}


def randomize_knobs(table: pd.DataFrame) -> dict[str, list[str]]:
    """Each scenario's parameters whose name says they randomize (``random_*``,
    ``*jitter*``, ``fixed``, ``noise``)."""
    from mimics.catalog import scenario_parameters

    found: dict[str, list[str]] = {}
    if "scenario_ref" not in table.columns:
        return found
    for scenario, ref in table.drop_duplicates("scenario")[["scenario", "scenario_ref"]].to_numpy(
            ):
        try:
            names = list(scenario_parameters(ref)) if not str(ref).endswith(".toml") else []
        except MimicsError:
            names = []
        found[scenario] = [n for n in names if n.startswith("random") or "jitter" in n
                           or n in ("fixed", "noise")]
    return found


def randomize_hints(table: pd.DataFrame) -> dict[str, str]:
    """Kept for callers that pass hints: none, so each cell's own cause is named."""
    return {}
