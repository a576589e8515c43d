"""Adjusted p-values against SciPy (Benjamini-Hochberg), a loop written from Holm's
definition, a worked textbook example and hypothesis properties."""

from __future__ import annotations

import doctest
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats as scipy_stats

from mimics.batteries import multiplicity
from mimics.batteries.multiplicity import ADJUST_METHODS, adjust_p_values, count_tests

p_value = st.floats(0.0, 1.0, allow_nan=False)
maybe_p_value = st.one_of(p_value, st.just(math.nan))


def holm_by_definition(p_values: list[float]) -> list[float]:
    """Holm's adjusted p-value of each test: the largest min(1, (m - j + 1) p_(j)) over the
    tests j ranked at or before it (Holm 1979; Wright 1992, Biometrics 48:1005-1013)."""
    m = len(p_values)
    ranked = sorted(range(m), key=lambda index: p_values[index])
    adjusted = [0.0] * m
    for rank, index in enumerate(ranked, start=1):
        adjusted[index] = max(min(1.0, (m - j + 1) * p_values[ranked[j - 1]])
                              for j in range(1, rank + 1))
    return adjusted


def test_holm_textbook_example() -> None:
    # four hypotheses at alpha 0.05 (the Holm-Bonferroni worked example): sorted
    # 0.005, 0.01, 0.03, 0.04 are compared with 0.05/4, 0.05/3, 0.05/2, 0.05/1, so H4
    # and H1 are rejected and the procedure stops at H3; adjusted: 4*0.005 = 0.02,
    # 3*0.01 = 0.03, then max(0.03, 2*0.03) = 0.06 and max(0.06, 1*0.04) = 0.06
    found = adjust_p_values([0.01, 0.04, 0.03, 0.005], "holm")
    assert found == pytest.approx([0.03, 0.06, 0.06, 0.02], abs=1e-15)
    assert list(found <= 0.05) == [True, False, False, True]


def test_bh_textbook_example() -> None:
    # Benjamini and Hochberg (1995) section 4: 15 p-values at q = 0.05 reject the four
    # smallest (the largest i with p_(i) <= 0.05 i / 15 is i = 4, p_(4) = 0.0095)
    published = [0.0001, 0.0004, 0.0019, 0.0095, 0.0201, 0.0278, 0.0298, 0.0344,
                 0.0459, 0.3240, 0.4262, 0.5719, 0.6528, 0.7590, 1.0000]
    found = adjust_p_values(published, "bh")
    assert int(np.count_nonzero(found <= 0.05)) == 4
    assert found == pytest.approx(scipy_stats.false_discovery_control(published), rel=1e-12)


@settings(max_examples=150, deadline=None)
@given(st.lists(p_value, min_size=1, max_size=40))
def test_bh_matches_scipy(p_values: list[float]) -> None:
    expected = scipy_stats.false_discovery_control(np.array(p_values), method="bh")
    assert adjust_p_values(p_values, "bh") == pytest.approx(expected, rel=1e-12, abs=1e-15)


@settings(max_examples=150, deadline=None)
@given(st.lists(p_value, min_size=1, max_size=40))
def test_holm_matches_its_definition(p_values: list[float]) -> None:
    found = adjust_p_values(p_values, "holm")
    assert found == pytest.approx(holm_by_definition(p_values), rel=1e-12, abs=1e-15)


@settings(max_examples=200, deadline=None)
@given(st.lists(maybe_p_value, min_size=0, max_size=40), st.sampled_from(ADJUST_METHODS))
def test_adjusted_values_are_honest(p_values: list[float], method: str) -> None:
    raw = np.array(p_values, dtype=float)
    found = adjust_p_values(p_values, method)
    missing = np.isnan(raw)
    assert found.shape == raw.shape
    assert np.array_equal(np.isnan(found), missing)
    kept, adjusted = raw[~missing], found[~missing]
    assert np.all(adjusted >= kept) and np.all(adjusted <= 1.0)
    # a smaller raw p-value never gets a larger adjusted one
    for i in range(len(kept)):
        for j in range(len(kept)):
            if kept[i] <= kept[j]:
                assert adjusted[i] <= adjusted[j]
    # NaN entries are not tests: adjusting only the present ones gives the same values
    if len(kept):
        assert adjusted == pytest.approx(adjust_p_values(kept, method), abs=0)
    assert count_tests(p_values) == len(kept)
    if method == "none":
        assert np.array_equal(found, raw, equal_nan=True)


def test_missing_p_values_and_counts() -> None:
    assert count_tests([0.1, None, math.nan, 0.2]) == 2
    found = adjust_p_values([0.02, None, 0.01], "holm")
    assert math.isnan(found[1]) and list(found[[0, 2]]) == pytest.approx([0.02, 0.02])
    assert adjust_p_values([], "bh").shape == (0,)
    assert np.isnan(adjust_p_values([math.nan, math.nan], "bh")).all()


def test_bad_input_is_named() -> None:
    with pytest.raises(ValueError, match=r"method: expected one of none, holm, bh, got 'bonf'"):
        adjust_p_values([0.1], "bonf")
    with pytest.raises(ValueError, match=r"p_values: expected values in \[0, 1\]"):
        adjust_p_values([0.1, 1.5], "holm")
    with pytest.raises(ValueError, match="1-D"):
        count_tests([[0.1, 0.2]])


def test_docstring_examples() -> None:
    assert doctest.testmod(multiplicity).failed == 0
