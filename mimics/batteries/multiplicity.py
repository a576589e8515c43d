"""Adjusted p-values for many comparisons at once (a battery compares many cells).

Testing m cells at 0.05 each finds about 0.05 m "differences" where there are
none. :func:`adjust_p_values` returns adjusted p-values, each compared with 0.05
as it stands:

- ``"holm"``: Holm (1979), "A simple sequentially rejective multiple test
  procedure", Scandinavian Journal of Statistics 6:65-70; step-down, controls
  the family-wise error rate (the chance of any false claim);
- ``"bh"``: Benjamini and Hochberg (1995), "Controlling the false discovery
  rate", Journal of the Royal Statistical Society B 57:289-300; step-up,
  controls the expected share of false claims among the claims;
- ``"none"``: the p-values unchanged.

NaN (or None) marks a comparison without a p-value: it stays NaN and is not
counted among the tests.

>>> adjust_p_values([0.01, 0.04, 0.03, float("nan")], "holm").round(2).tolist()
[0.03, 0.06, 0.06, nan]
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

ADJUST_METHODS = ("none", "holm", "bh")


def _p_values(p_values: np.ndarray | Sequence[float | None]) -> np.ndarray:
    """The p-values as a 1-D float array (None as NaN), checked to lie in [0, 1]."""
    values = np.asarray(p_values, dtype=float)
    if values.ndim != 1:
        raise ValueError(f"p_values: expected a 1-D sequence, got shape {values.shape}")
    outside = ~np.isnan(values) & ((values < 0) | (values > 1))
    if outside.any():
        raise ValueError(f"p_values: expected values in [0, 1] or NaN, "
                         f"got {float(values[outside][0])}")
    return values


def count_tests(p_values: np.ndarray | Sequence[float | None]) -> int:
    """How many comparisons have a p-value (non-NaN entries)."""
    return int(np.count_nonzero(~np.isnan(_p_values(p_values))))


def _holm(ordered: np.ndarray) -> np.ndarray:
    """Holm's adjusted values of ascending p-values: running max of (m - i) p_(i)."""
    m = len(ordered)
    scaled = (m - np.arange(m)) * ordered
    return np.minimum(1.0, np.maximum.accumulate(scaled))


def _benjamini_hochberg(ordered: np.ndarray) -> np.ndarray:
    """BH's adjusted values of ascending p-values: running min, from the top, of m p_(i) / i."""
    m = len(ordered)
    scaled = m * ordered / np.arange(1, m + 1)
    return np.minimum(1.0, np.minimum.accumulate(scaled[::-1])[::-1])


def adjust_p_values(p_values: np.ndarray | Sequence[float | None], method: str) -> np.ndarray:
    """Adjusted p-values in the input order (NaN stays NaN, not counted as a test).

    Raises:
        ValueError: for an unknown ``method``, or p-values outside [0, 1].
    """
    if method not in ADJUST_METHODS:
        raise ValueError(f"method: expected one of {', '.join(ADJUST_METHODS)}, got {method!r}")
    values = _p_values(p_values)
    adjusted = values.copy()
    tested = np.flatnonzero(~np.isnan(values))
    if method == "none" or len(tested) == 0:
        return adjusted
    order = tested[np.argsort(values[tested], kind="stable")]
    step = _holm if method == "holm" else _benjamini_hochberg
    # m p / m can round one ulp below p; an adjusted p-value is never below the raw one
    adjusted[order] = np.maximum(values[order], step(values[order]))
    return adjusted
