"""Batteries that stop when the answer is known: the ``[battery.until]`` rule.

::

    [battery.until]
    metric = "time_to_goal"   # any per-run metric (mimics.batteries.metrics.METRICS)
    half_width = 0.2          # stop a cell when its 95% interval is at most this wide each side
    min_seeds = 10            # the first round
    max_seeds = 500           # never more

Each cell (algorithm x scenario x parameter point) runs seeds 1, 2, 3... in
rounds. The first round is seeds 1..min_seeds; when every run of a round has
finished, the cell's 95% interval of the metric's mean (Student-t; Wilson for
the ``success`` proportion) is computed over those seeds, and the cell stops
when its half-width is at most ``half_width`` or it has ``max_seeds`` seeds.
Otherwise the next round reaches the number of seeds that the current spread
says is needed, at least one more seed and at most twice as many (a small
first sample underestimates the spread often enough that a single jump to
the estimate overshoots or undershoots; doubling bounds both).

The schedule is a pure function of the finished runs: :func:`cell_progress`
walks the rounds from ``min_seeds`` using only the values of each completed
round, so a battery resumed after a kill decides exactly the rounds it would
have decided, whatever the order in which runs finished.

A run whose metric is undefined (it failed, or reached no goal for
``time_to_goal``) counts as a seed used but gives no value; with fewer than
two values the half-width is infinite and the cell goes on (to ``max_seeds``
if need be). The interval is then of the mean over the runs where the metric
is defined: time to goal is conditional on reaching the goal.

>>> rule = UntilRule("collisions", 0.5, min_seeds=3, max_seeds=10)
>>> cell_progress({1: 0.0, 2: 0.0, 3: 0.0}, rule).complete
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from mimics.batteries.metrics import METRICS
from mimics.batteries.stats import _t_quantile, finite, proportion_interval, t_interval

UNTIL_KEYS = ("metric", "half_width", "min_seeds", "max_seeds")
DEFAULT_MIN_SEEDS = 10
DEFAULT_MAX_SEEDS = 500


@dataclass(frozen=True)
class UntilRule:
    """When a cell of the battery has run enough seeds.

    Attributes:
        metric: the per-run metric whose mean is estimated.
        half_width: the target half-width of its 95% interval.
        min_seeds: seeds of the first round.
        max_seeds: seeds at most.
    """

    metric: str
    half_width: float
    min_seeds: int = DEFAULT_MIN_SEEDS
    max_seeds: int = DEFAULT_MAX_SEEDS


@dataclass(frozen=True)
class CellProgress:
    """Where one cell stands.

    Attributes:
        scheduled: seeds 1..scheduled belong to the cell's rounds so far.
        finished: how many of them have finished.
        half_width: the half-width over the last completed round (inf: none yet or
            fewer than two values).
        complete: the cell needs no more seeds.
    """

    scheduled: int
    finished: int
    half_width: float
    complete: bool


def half_width(values: np.ndarray | list[float], metric: str) -> float:
    """The half-width of the 95% interval of the metric's mean (NaN values left out)."""
    if METRICS[metric].proportion:
        return proportion_interval(values).half_width
    return t_interval(values).half_width


def next_round(values: list[float], rule: UntilRule) -> int:
    """Seeds the cell should have after a round of ``len(values)`` seeds that missed its target.

    The estimate is ``(t * s / half_width)^2`` values, scaled up by the share of
    seeds whose value was undefined; bounded to one more seed at least, twice as
    many at most, and ``max_seeds``.
    """
    seeds = len(values)
    data = finite(values)
    if len(data) >= 2:
        if METRICS[rule.metric].proportion:  # the normal approximation's sample size
            p = float(data.mean())
            spread = math.sqrt(max(p * (1 - p), 1.0 / len(data)))
        else:
            spread = float(data.std(ddof=1))
        needed = (_t_quantile(len(data) - 1) * spread / rule.half_width) ** 2
        wanted = math.ceil(needed * seeds / len(data))
    else:
        wanted = 2 * seeds
    return int(min(rule.max_seeds, 2 * seeds, max(seeds + 1, wanted)))


def cell_progress(values: dict[int, float], rule: UntilRule) -> CellProgress:
    """The cell's rounds, recomputed from its finished runs.

    Args:
        values: seed -> the metric's value (NaN when undefined), for the finished runs.
        rule: the stopping rule.
    """
    scheduled = min(rule.min_seeds, rule.max_seeds)
    width = math.inf
    while True:
        round_values = [values[s] for s in range(1, scheduled + 1) if s in values]
        if len(round_values) < scheduled:  # the round is still running
            return CellProgress(scheduled, len(round_values), width, False)
        width = half_width(round_values, rule.metric)
        if width <= rule.half_width or scheduled >= rule.max_seeds:
            return CellProgress(scheduled, scheduled, width, True)
        scheduled = next_round(round_values, rule)


def parse_until(value: Any, fail: Any) -> UntilRule:
    """A ``[battery.until]`` table, checked.

    Raises:
        whatever ``fail(message)`` returns, with a message naming the field.
    """
    where = "[battery.until]"
    if not isinstance(value, dict):
        raise fail(f"{where}: expected a table with metric and half_width, got {value!r}")
    for key in value:
        if key not in UNTIL_KEYS:
            raise fail(f"{where}: unknown key {key!r} (expected one of: {', '.join(UNTIL_KEYS)})")
    metric = value.get("metric")
    if metric not in METRICS:
        raise fail(f"{where} metric: expected one of {', '.join(METRICS)}, got {metric!r}")
    width = value.get("half_width")
    if (not isinstance(width, int | float) or isinstance(width, bool) or not math.isfinite(width)
            or width <= 0):
        raise fail(f"{where} half_width: expected a positive number, got {width!r}")
    counts = {}
    for key, default in (("min_seeds", DEFAULT_MIN_SEEDS), ("max_seeds", DEFAULT_MAX_SEEDS)):
        count = value.get(key, default)
        if isinstance(count, bool) or not isinstance(count, int) or not 2 <= count <= 1_000_000:
            raise fail(f"{where} {key}: expected a whole number from 2 to 1000000, got {count!r}")
        counts[key] = count
    if counts["min_seeds"] > counts["max_seeds"]:
        raise fail(f"{where} min_seeds: {counts['min_seeds']} is more than max_seeds "
                   f"{counts['max_seeds']}")
    return UntilRule(metric, float(width), counts["min_seeds"], counts["max_seeds"])


def parse_until_option(text: str, fail: Any, base: UntilRule | None = None) -> UntilRule:
    """``--until METRIC:HALF_WIDTH``; seeds bounds from ``base`` (the file's rule) or defaults.

    Raises:
        whatever ``fail(message)`` returns, with a message naming ``--until``.
    """
    metric, sep, width_text = text.partition(":")
    if not sep:
        raise fail(f"--until {text!r}: expected METRIC:HALF_WIDTH, e.g. time_to_goal:0.2")
    try:
        width = float(width_text)
    except ValueError:
        raise fail(f"--until {text!r}: the half-width {width_text!r} is not a number") from None
    table: dict[str, Any] = {"metric": metric.strip(), "half_width": width}
    if base is not None:
        table.update(min_seeds=base.min_seeds, max_seeds=base.max_seeds)

    def named(message: str) -> Any:
        return fail(message.replace("[battery.until]", "--until"))

    return parse_until(table, named)
