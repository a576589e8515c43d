"""The tests' TOML writer (tests/toml_text.py) against Python's own TOML reader."""

from __future__ import annotations

import tomllib
from typing import Any

from hypothesis import given
from hypothesis import strategies as st

from tests.toml_text import toml_text

KEYS = st.text("abcdefghijklmnopqrstuvwxyz_0123456789", min_size=1, max_size=8)
SCALARS = st.one_of(st.booleans(), st.integers(-10**12, 10**12),
                    st.floats(allow_nan=False, allow_infinity=False),
                    st.text(st.characters(min_codepoint=32, max_codepoint=126), max_size=12))
VALUES = st.recursive(SCALARS, lambda inner: st.lists(inner, max_size=3)
                      | st.dictionaries(KEYS, inner, min_size=1, max_size=3), max_leaves=8)
TABLES = st.dictionaries(KEYS, VALUES, min_size=1, max_size=4)


@st.composite
def documents(draw: Any) -> dict[str, Any]:
    """Plain keys, an array of tables, a table of tables and a table, as the tests use."""
    names = draw(st.lists(KEYS, min_size=4, max_size=4, unique=True))
    plain = draw(st.dictionaries(KEYS.filter(lambda key: key not in names), SCALARS,
                                 max_size=3))
    return {**plain, names[0]: draw(st.lists(TABLES, min_size=1, max_size=3)),
            names[1]: draw(st.dictionaries(KEYS, TABLES, min_size=1, max_size=2)),
            names[2]: draw(st.dictionaries(KEYS, SCALARS, min_size=1, max_size=3))}


@given(documents())
def test_what_it_writes_reads_back_as_the_same_document(document: dict[str, Any]) -> None:
    text = toml_text(document)
    assert tomllib.loads(text) == document, text


def test_each_key_stands_on_a_line_of_its_own() -> None:
    text = toml_text({"name": "a", "robots": [{"x": 1.0, "goal": [8.0, 2.0]}],
                      "types": {"Small": {"width": 0.2, "ranger": {"beams": 90}}},
                      "settings": {"dt": 0.1}})
    assert text == ('name = "a"\n\n[[robots]]\nx = 1.0\ngoal = [8.0, 2.0]\n\n'
                    '[types.Small]\nwidth = 0.2\nranger = { beams = 90 }\n\n'
                    '[settings]\ndt = 0.1\n')
