"""The statistics of batteries: intervals, paired differences, signed-rank tests.

Pure functions on arrays (no printing, no files), used by the report, ``mimics
battery compare``, the stopping rule and the workbench:

- :func:`t_interval`: the mean and its 95% Student-t interval;
- :func:`wilson_interval`: a proportion (a success rate) and its 95% Wilson
  score interval, right also near 0 and 1 where the normal interval is not;
- :func:`bootstrap_interval`: the mean and its 95% bias-corrected and
  accelerated (BCa) bootstrap interval (Efron 1987; :func:`scipy.stats.bootstrap`),
  for skewed metrics where the t interval's symmetry misleads;
- :func:`paired_difference`: the mean of paired differences (same scenario,
  parameters and seed), its t interval, and the two-sided Wilcoxon signed-rank
  p-value (:func:`scipy.stats.wilcoxon`), or the reason there is none.

>>> t_interval(np.array([1.0, 2.0, 3.0])).half_width
2.484...
>>> round(wilson_interval(9, 10).low, 4)
0.5958
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

CONFIDENCE = 0.95
#: Non-zero differences below which a two-sided signed-rank test cannot reach p < 0.05
#: (its smallest exact p-value is 2 / 2**n: 0.0625 with five).
MIN_SIGNED_RANK = 6


@dataclass(frozen=True)
class Interval:
    """An estimate and its 95% interval.

    Attributes:
        estimate: the mean (or the proportion); NaN without values.
        low: the interval's lower end (NaN when it cannot be computed).
        high: its upper end.
        n: how many values it rests on.
    """

    estimate: float
    low: float
    high: float
    n: int

    @property
    def half_width(self) -> float:
        """Half the interval's width (infinite when there is no interval)."""
        if math.isnan(self.low) or math.isnan(self.high):
            return math.inf
        return (self.high - self.low) / 2.0

    @property
    def degenerate(self) -> bool:
        """True when the interval is a single point: values without spread (n >= 1).

        A zero-width interval says "no spread in this sample", not "known exactly";
        a report should say so rather than print ``1.00 [1.00, 1.00]`` as if certain.
        One value (NaN ends: no interval at all) is not degenerate.
        """
        return self.n >= 1 and self.low == self.high == self.estimate


@dataclass(frozen=True)
class PairedDifference:
    """An algorithm minus its baseline, pair by pair.

    Attributes:
        interval: the mean difference and its 95% t interval.
        p_value: the two-sided Wilcoxon signed-rank p-value (None: see ``note``).
        note: why there is no p-value ("" when there is one).
    """

    interval: Interval
    p_value: float | None
    note: str


def _t_quantile(dof: int) -> float:
    from scipy.stats import t

    return float(t.ppf(0.5 + CONFIDENCE / 2, dof))


def _z_quantile() -> float:
    from scipy.stats import norm

    return float(norm.ppf(0.5 + CONFIDENCE / 2))


def finite(values: np.ndarray | list[float]) -> np.ndarray:
    """The values as floats, NaN (undefined) dropped."""
    array = np.asarray(values, dtype=float)
    return array[~np.isnan(array)]


def t_interval(values: np.ndarray | list[float]) -> Interval:
    """The mean and its 95% Student-t interval (NaN ends with fewer than two values).

    NaN values (undefined, such as a time to goal that was never reached) are left out.
    """
    data = finite(values)
    n = len(data)
    if n == 0:
        return Interval(math.nan, math.nan, math.nan, 0)
    mean = float(data.mean())
    if n < 2:
        return Interval(mean, math.nan, math.nan, 1)
    if data.min() == data.max():  # no spread: exactly, not the rounding of a mean
        return Interval(mean, mean, mean, n)
    half = _t_quantile(n - 1) * float(data.std(ddof=1)) / math.sqrt(n)
    return Interval(mean, mean - half, mean + half, n)


def bootstrap_interval(values: np.ndarray | list[float], *, seed: int = 0,
                       resamples: int = 9999) -> Interval:
    """The mean and its 95% BCa bootstrap interval, reproducible from ``seed``.

    NaN values are left out. As :func:`t_interval`: no values give NaN
    everywhere, one value NaN ends, values without spread a point interval
    (BCa's acceleration is 0/0 there).

    Raises:
        ValueError: when ``resamples`` is below 1.
    """
    if resamples < 1:
        raise ValueError(f"resamples: expected at least 1, got {resamples}")
    data = finite(values)
    n = len(data)
    if n == 0:
        return Interval(math.nan, math.nan, math.nan, 0)
    mean = float(data.mean())
    if n < 2:
        return Interval(mean, math.nan, math.nan, 1)
    if data.min() == data.max():
        return Interval(mean, mean, mean, n)
    from scipy.stats import bootstrap

    result = bootstrap((data,), np.mean, n_resamples=resamples, confidence_level=CONFIDENCE,
                       method="BCa", random_state=np.random.default_rng(seed))
    ends = result.confidence_interval
    return Interval(mean, float(ends.low), float(ends.high), n)


def wilson_interval(successes: int, n: int) -> Interval:
    """A proportion and its 95% Wilson score interval.

    Raises:
        ValueError: when ``successes`` is not within 0..n.
    """
    if not 0 <= successes <= n:
        raise ValueError(f"successes: expected 0..{n}, got {successes}")
    if n == 0:
        return Interval(math.nan, math.nan, math.nan, 0)
    z = _z_quantile()
    p = successes / n
    denominator = 1 + z * z / n
    centre = (p + z * z / (2 * n)) / denominator
    half = z / denominator * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    low = 0.0 if successes == 0 else max(0.0, centre - half)  # exact ends, not rounded ones
    high = 1.0 if successes == n else min(1.0, centre + half)
    return Interval(p, low, high, n)


def proportion_interval(values: np.ndarray | list[float]) -> Interval:
    """The Wilson interval of 0/1 values (NaN left out)."""
    data = finite(values)
    return wilson_interval(int(np.count_nonzero(data)), len(data))


def paired_difference(candidate: np.ndarray | list[float],
                      baseline: np.ndarray | list[float]) -> PairedDifference:
    """``candidate - baseline``, pair by pair: mean, 95% t interval, Wilcoxon p-value.

    Pairs where either value is NaN (undefined) are left out. The signed-rank
    test drops zero differences (``zero_method="wilcox"``); with every difference
    zero, or fewer than :data:`MIN_SIGNED_RANK` non-zero ones, there is no
    p-value and ``note`` says why.

    Raises:
        ValueError: when the two arrays differ in length.
    """
    a = np.asarray(candidate, dtype=float)
    b = np.asarray(baseline, dtype=float)
    if a.shape != b.shape:
        raise ValueError(f"paired values: {a.shape} and {b.shape} differ in length")
    keep = ~(np.isnan(a) | np.isnan(b))
    differences = a[keep] - b[keep]
    interval = t_interval(differences)
    n = len(differences)
    nonzero = int(np.count_nonzero(differences))
    if n == 0:
        return PairedDifference(interval, None, "no pairs")
    if nonzero == 0:
        return PairedDifference(interval, None, f"all {n} differences are zero")
    if nonzero < MIN_SIGNED_RANK:
        return PairedDifference(interval, None, f"only {nonzero} non-zero difference(s): a "
                                f"signed-rank test needs {MIN_SIGNED_RANK} to reach p < 0.05")
    from scipy.stats import wilcoxon

    result = wilcoxon(differences, zero_method="wilcox", alternative="two-sided")
    return PairedDifference(interval, float(result.pvalue), "")
